"""set_float: publish one std_msgs/Float64 on an effector input topic (latched), e.g. the
2008 harvester's roller speed (1: harvest, -1: unload, 0: off)."""
from smart_brain.actions import register_action
from smart_brain.statemachine import State

_pubs = {}


class SetFloat(State):
    def __init__(self, topic, value):
        State.__init__(self, outcomes=['succeeded'])
        import rospy
        from std_msgs.msg import Float64
        if topic not in _pubs:
            _pubs[topic] = rospy.Publisher(topic, Float64, queue_size=1, latch=True)
        self._pub = _pubs[topic]
        self._msg = Float64(float(value))

    def execute(self, ud):
        self._pub.publish(self._msg)
        return 'succeeded'


@register_action('set_float')
def set_float(topic, value):
    return SetFloat(topic, value)
