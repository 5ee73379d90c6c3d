"""opponent_ahead: while the robot drives, a ranger in the driving direction sees something nearer
than `distance`.

Config: ~triggers/opponent_ahead, each key described where read() reads it (smart_brain/PARAMETERS.md).
An echo the table border explains (border_tolerance set; border_echo.py; the table's size from
the brain's TableSettings) is not the opponent.

Fires -> zero wheel speed at once, the running state is preempted (its driver goal
cancelled), the handler waits for the way to clear, then the state resumes.
It fires only while the robot moves (/odom, faster than MOVING m/s): standing or turning in place
beside an opponent drives into nothing, and firing then preempted every new goal at its start (a
robot next to a parked opponent never left). The driver's avoidance still guards the route. The
handler waits on the echoes alone (the robot it stopped is not moving).
"""
import threading

from smart_brain.statemachine import clock
from smart_brain.statemachine import Trigger
from smart_brain.triggers import decision_param
from smart_brain.triggers.wait_clear import WaitClear
from smart_brain.actions.stop import publish_zero

KIND = 'opponent_ahead'
MOVING = 0.01  # [m/s] /odom's forward speed above which the robot drives (below: standing or turning)


class RangerWatch(object):
    def __init__(self, front, rear, distance, max_age, notify, border=None):
        import rospy
        from nav_msgs.msg import Odometry
        from sensor_msgs.msg import Range
        self.distance = distance
        self.max_age = max_age
        self._lock = threading.Lock()
        self._latest = {}     # name -> (monotonic receive time, range)
        self._backwards = False
        self._moving = False
        self._front, self._rear = list(front), list(rear)
        self._notify = notify
        self._border = border
        self._subs = [rospy.Subscriber('/hal/rangers/' + n, Range, self._on_range, callback_args=n, queue_size=1)
                      for n in self._front + self._rear]
        self._subs.append(rospy.Subscriber('/odom', Odometry, self._on_odom, queue_size=1))

    def _on_range(self, msg, name):
        near = msg.min_range <= msg.range < self.distance and msg.range <= msg.max_range
        if near and self._border is not None and self._border.explains(msg):
            near = False
        with self._lock:
            self._latest[name] = (clock.now(), near)
        if near:
            self._notify()   # poll the trigger now, not at the next supervisor tick

    def _on_odom(self, msg):
        v = msg.twist.twist.linear.x
        self._moving = abs(v) > MOVING
        if self._moving:
            self._backwards = v < 0.0  # kept while stopped: the handler watches the way it was going

    def __call__(self):
        """The trigger's condition: driving, and an echo near in the driving direction."""
        return self._moving and self.near()

    def near(self):
        """An echo nearer than `distance` in the driving direction (the last one, when stopped)."""
        names = self._rear if self._backwards and self._rear else self._front
        now = clock.now()
        with self._lock:
            return any(n in self._latest and now - self._latest[n][0] <= self.max_age and self._latest[n][1]
                       for n in names)


def read(cfg):
    return dict(
        rangers=cfg.get('rangers', [], list, meaning='names under /hal/rangers/ looking forwards'),
        rear_rangers=cfg.get('rear_rangers', [], list, meaning='the rangers watched while driving backwards'),
        distance=cfg.get('distance', 0.3, meaning='[m] an echo nearer than this in the driving direction fires it'),
        max_age=cfg.get('max_age', 0.5, meaning='[s] an older reading no longer counts'),
        debounce=cfg.get('debounce', 0.0, meaning='[s] seen this long before it fires'),
        holdoff=cfg.get('holdoff', 1.0, meaning='[s] after its handler ends, it does not fire again for this long'),
        border_tolerance=cfg.get('border_tolerance', -1.0, meaning='[m] >= 0: an echo the table border explains '
                                 'from the pose, within this, is not the opponent (< 0: off)'),
        clear_time=cfg.get('clear_time', 0.5, meaning='[s] the way is clear this long before the state resumes'),
        max_wait=cfg.get('max_wait', 3.0, meaning='[s] longest wait for the way to clear'),
        then=decision_param(cfg),
        table=cfg.table.size)


def make(s):
    front, rear, distance, max_age, debounce, holdoff, border_tolerance = (
        s['rangers'], s['rear_rangers'], s['distance'], s['max_age'], s['debounce'], s['holdoff'], s['border_tolerance'])
    handler_args = dict(clear_time=s['clear_time'], max_wait=s['max_wait'], then=s['then'])
    trig = Trigger(KIND, None, None, debounce=debounce, holdoff=holdoff, priority=2, on_fire=publish_zero)
    border = None
    if border_tolerance >= 0.0:
        from smart_brain.triggers.border_echo import BorderEcho
        border = BorderEcho(s['table'][0], s['table'][1], border_tolerance)
    watch = RangerWatch(front, rear, distance, max_age, trig.notify, border)
    trig.condition = watch
    trig.handler = WaitClear(watch.near, **handler_args)
    return trig
