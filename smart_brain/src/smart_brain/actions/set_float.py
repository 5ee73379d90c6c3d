"""set_float: publish one std_msgs/Float64 on an effector input topic (latched), e.g. the
2008 harvester's roller speed (1: harvest, -1: unload, 0: off)."""
from smart_brain.actions import register_action
from smart_brain.statemachine import State

_pubs = {}


class SetFloat(State):
    def __init__(self, topic, value):
        State.__init__(self, outcomes=['succeeded'])
        self.topic = topic
        self.value = float(value)

    def execute(self, ud):
        # Latched: a subscriber that connects after this publish still gets the setting.
        import rospy
        from std_msgs.msg import Float64
        if self.topic not in _pubs:
            _pubs[self.topic] = rospy.Publisher(self.topic, Float64, queue_size=1, latch=True)
        _pubs[self.topic].publish(Float64(self.value))
        return 'succeeded'


@register_action('set_float')
def set_float(topic, value):
    return SetFloat(topic, value)
