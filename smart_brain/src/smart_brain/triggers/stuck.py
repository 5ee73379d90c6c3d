"""stuck: a configured bumper contact is closed (the robot is pushing a border or the
opponent). Handler: stop, back off `back_off` metres from odometry (go_straight
backwards), then the decision `after_back_off` (default resume: the interrupted state goes on;
aborted: it ends aborted, so the strategy chooses again instead of driving back into the same
contact), or `then` if backing off failed.

Config (~triggers/stuck): contacts (names in /hal/bumpers/contacts), back_off [m],
debounce (default 0.2 s: a brush against a border is not stuck), holdoff, after_back_off, then.
"""
import threading

from smart_brain.actions.stop import StopState
from smart_brain.statemachine import StateMachine, Trigger
from smart_brain.triggers import Config, decision_param

KIND = 'stuck'


class ContactWatch(object):
    def __init__(self, names, notify):
        import rospy
        from hal_nodes.msg import Contacts
        self._names = set(names)
        self._closed = False
        self._lock = threading.Lock()
        self._notify = notify
        self._sub = rospy.Subscriber('/hal/bumpers/contacts', Contacts, self._on_msg, queue_size=5)

    def _on_msg(self, msg):
        closed = bool(self._names & set(msg.closed)) if self._names else bool(msg.closed)
        with self._lock:
            self._closed = closed
        if closed:
            self._notify()

    def __call__(self):
        return self._closed


def make(values):
    from smart_brain.actions.go_straight import go_straight
    cfg = Config(KIND, values)
    contacts = cfg.get('contacts', [], list)
    back_off = cfg.get('back_off', 0.1)
    debounce = cfg.get('debounce', 0.2)
    holdoff = cfg.get('holdoff', 1.0)
    then = decision_param(cfg)
    after = decision_param(cfg, 'after_back_off')
    cfg.done()
    handler = StateMachine(outcomes=sorted({after, then, 'preempted'}))
    handler.add('STOP', StopState(), transitions={'succeeded': 'BACK_OFF'})
    handler.add('BACK_OFF', go_straight(back_off, backwards=True, exec_timeout=5.0),
                transitions={'succeeded': after, 'aborted': then, 'preempted': 'preempted'})
    trig = Trigger(KIND, None, handler, debounce=debounce, holdoff=holdoff, priority=3)
    trig.condition = ContactWatch(contacts, trig.notify)
    return trig
