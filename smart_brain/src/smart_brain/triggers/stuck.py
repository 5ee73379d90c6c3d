"""stuck: a configured bumper contact is closed (the robot is pushing a border or the
opponent). Handler: stop, back off `back_off` metres from odometry (go_straight
backwards), then the decision `after_back_off` (default resume: the interrupted state goes on;
aborted: it ends aborted, so the strategy chooses again instead of driving back into the same
contact), or `then` if backing off failed.

Config: ~triggers/stuck, each key described where read() reads it (smart_brain/PARAMETERS.md).
"""
import threading

from smart_brain.actions.stop import StopState
from smart_brain.statemachine import StateMachine, Trigger
from smart_brain.triggers import decision_param

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


def read(cfg):
    return dict(
        contacts=cfg.get('contacts', [], list, meaning='names in /hal/bumpers/contacts that mean stuck (empty: any)'),
        back_off=cfg.get('back_off', 0.1, meaning='[m] how far it backs off, by odometry'),
        debounce=cfg.get('debounce', 0.2, meaning='[s] closed this long before it fires (a brush is not stuck)'),
        holdoff=cfg.get('holdoff', 1.0, meaning='[s] after its handler ends, it does not fire again for this long'),
        then=decision_param(cfg, meaning='the decision when backing off failed'),
        after=decision_param(cfg, 'after_back_off', meaning='the decision after backing off: resume (the interrupted '
                             'state goes on), aborted (the strategy chooses again), restart or a state label'))


def make(s):
    from smart_brain.actions.go_straight import go_straight
    contacts, back_off, debounce, holdoff, then, after = (
        s['contacts'], s['back_off'], s['debounce'], s['holdoff'], s['then'], s['after'])
    handler = StateMachine(outcomes=sorted({after, then, 'preempted'}))
    handler.add('STOP', StopState(), transitions={'succeeded': 'BACK_OFF'})
    handler.add('BACK_OFF', go_straight(back_off, backwards=True, exec_timeout=5.0),
                transitions={'succeeded': after, 'aborted': then, 'preempted': 'preempted'})
    trig = Trigger(KIND, None, handler, debounce=debounce, holdoff=holdoff, priority=3)
    trig.condition = ContactWatch(contacts, trig.notify)
    return trig
