"""stop: zero wheel speed now on /hal/drive/cmd_vel (the drive effector's input) and
cancel whatever the driver is doing; used by trigger handlers before deciding."""
from smart_brain.actions import register_action
from smart_brain.statemachine import State

CMD_VEL = '/hal/drive/cmd_vel'
_pubs = {}


def prepare(topic=CMD_VEL):
    """Advertise early: a publisher made at the moment of need has no subscriber connected yet."""
    import rospy
    from geometry_msgs.msg import Twist
    if topic not in _pubs:
        _pubs[topic] = rospy.Publisher(topic, Twist, queue_size=1)
    return _pubs[topic]


def publish_zero(topic=CMD_VEL, times=1):
    from geometry_msgs.msg import Twist
    pub = prepare(topic)
    for _ in range(times):
        pub.publish(Twist())


class StopState(State):
    def __init__(self, topic=CMD_VEL):
        State.__init__(self, outcomes=['succeeded'])
        self.topic = topic

    def execute(self, ud):
        publish_zero(self.topic)
        return 'succeeded'


@register_action('stop')
def stop(topic=CMD_VEL):
    return StopState(topic)
