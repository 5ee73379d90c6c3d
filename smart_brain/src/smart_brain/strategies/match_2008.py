"""The 2008 match ("Mission to Mars", Logion): harvest the balls the camera sees along a
Hermite path and deliver them.

Loop: take the balls of our kinds the vision device sees now (nearest-first, up to
`max_balls` per trip), switch the harvester on, follow one Hermite path through them
(/hal/driver/follow_path), drive to the basket, unload, again. When no ball is seen,
drive the configured search path and look again; after `max_searches` empty looks the
machine ends, and the strategy starts it again after a back-off (balls roll, the opponent
moves them): it plays until the match ends (MachineStrategy.restart_on). Balls seen closer than `border_margin` to a border are left: the harvester cannot take one lying
against the border without the robot pushing it, and a detection on the border line is none.
Config: ~match2008/{ball_kinds, max_balls, basket, search, max_searches, border_margin,
harvester_topic, harvester_speed, unload_speed, unload_time, vision_topic}. The harvester
is an effector input (std_msgs/Float64, its speed); with harvester_topic empty the
harvester is passive (a fixed brush) and unloading is just waiting at the basket.
"""
import math

from smart_brain.actions.follow_path import follow_path
from smart_brain.actions.goto import goto
from smart_brain.machine_strategy import MachineStrategy
from smart_brain.statemachine import CBState, Retry, StateMachine, WaitState
from smart_brain.strategy import register
from smart_brain.world_view import WorldView, nearest_first


@register
class Match2008Strategy(MachineStrategy):
    name = 'match2008'
    description = '2008: harvest the balls the camera sees along a Hermite path, deliver them to the basket'
    required_devices = ('driver',)
    required_topics = ('/mcl/pose',)
    restart_on = ('aborted', 'succeeded')

    def next_round(self, outcome):
        self.searches = 0
        return True

    def build(self):
        import rospy
        from std_msgs.msg import Float64
        self.kinds = list(self.param('ball_kinds', ['ball_red', 'ball_white']))
        self.max_balls = int(self.param('max_balls', 3))
        basket = tuple(float(v) for v in self.param('basket', [0.25, 1.75, math.pi]))
        search = [tuple(p) for p in self.param('search', [[1.0, 1.0], [2.0, 1.0], [2.0, 0.5]])]
        self.max_searches = int(self.param('max_searches', 3))
        topic = self.param('harvester_topic', '')
        self.speed = float(self.param('harvester_speed', 1.0))
        self.unload_speed = float(self.param('unload_speed', -1.0))
        self.world = WorldView(self.param('vision_topic', '/hal/vision/elements'),
                               border_margin=float(self.param('border_margin', 0.08)))
        self.harvester = rospy.Publisher(topic, Float64, queue_size=1, latch=True) if topic else None
        self.searches = 0

        sm = StateMachine(outcomes=['succeeded', 'aborted', 'preempted'])
        sm.userdata.path = []
        sm.userdata.basket = basket
        with sm:
            StateMachine.add('LOOK', CBState(self._look, outcomes=['balls', 'none', 'give_up'], output_keys=['path']),
                             transitions={'balls': 'HARVEST_ON', 'none': 'SEARCH', 'give_up': 'succeeded'})
            StateMachine.add('HARVEST_ON', CBState(self._harvester, outcomes=['on'], cb_args=(self.speed,)),
                             transitions={'on': 'HARVEST'})
            StateMachine.add('HARVEST', follow_path(points_key='path', exec_timeout=20.0),
                             transitions={'succeeded': 'DELIVER', 'aborted': 'DELIVER', 'preempted': 'preempted'})
            StateMachine.add('DELIVER', Retry(goto(pose_key='basket', exec_timeout=20.0), attempts=3),
                             transitions={'succeeded': 'UNLOAD', 'aborted': 'aborted', 'preempted': 'preempted'})
            StateMachine.add('UNLOAD', CBState(self._harvester, outcomes=['on'], cb_args=(self.unload_speed,)),
                             transitions={'on': 'UNLOADING'})
            StateMachine.add('UNLOADING', WaitState(float(self.param('unload_time', 1.5))),
                             transitions={'succeeded': 'LOOK', 'preempted': 'preempted'})
            StateMachine.add('SEARCH', follow_path(points=search, exec_timeout=25.0),
                             transitions={'succeeded': 'LOOK', 'aborted': 'LOOK', 'preempted': 'preempted'})
        return sm

    def _harvester(self, ud, speed):
        from std_msgs.msg import Float64
        if self.harvester is not None:
            self.harvester.publish(Float64(speed))
        return 'on'

    def _look(self, ud):
        balls = [(x, y) for _, x, y in self.world.elements(self.kinds)]
        if not balls:
            self.searches += 1
            return 'give_up' if self.searches > self.max_searches else 'none'
        self.searches = 0
        start = self.world.pose() or balls[0]
        ud.path = nearest_first(start, balls)[:self.max_balls]
        return 'balls'

    def finalize(self):
        MachineStrategy.finalize(self)
        if getattr(self, 'harvester', None) is not None:
            from std_msgs.msg import Float64
            self.harvester.publish(Float64(0.0))
