"""topic_flag: a std_msgs/Bool topic says "stop" (a custom sensor, an operator, a test).

Config: ~triggers/topic_flag, each key described where read() reads it (smart_brain/PARAMETERS.md).
Handler: as opponent_ahead (zero speed, wait until clear, resume).
"""
import threading

from smart_brain.statemachine import clock
from smart_brain.actions.stop import publish_zero
from smart_brain.statemachine import Trigger
from smart_brain.triggers import decision_param
from smart_brain.triggers.wait_clear import WaitClear

KIND = 'topic_flag'


class FlagWatch(object):
    def __init__(self, topic, max_age, notify):
        import rospy
        from std_msgs.msg import Bool
        self._lock = threading.Lock()
        self._value = (0.0, False)
        self.max_age = max_age
        self._notify = notify
        self._sub = rospy.Subscriber(topic, Bool, self._on_msg, queue_size=1)

    def _on_msg(self, msg):
        with self._lock:
            self._value = (clock.now(), msg.data)
        if msg.data:
            self._notify()

    def __call__(self):
        with self._lock:
            stamp, value = self._value
        return value and clock.now() - stamp <= self.max_age


def read(cfg):
    return dict(
        topic=cfg.get('topic', '/brain/stop_flag', str, meaning='the std_msgs/Bool topic that says stop'),
        max_age=cfg.get('max_age', 1.0, meaning='[s] an older True no longer counts'),
        debounce=cfg.get('debounce', 0.0, meaning='[s] True this long before it fires'),
        holdoff=cfg.get('holdoff', 0.5, meaning='[s] after its handler ends, it does not fire again for this long'),
        clear_time=cfg.get('clear_time', 0.3, meaning='[s] False this long before the state resumes'),
        max_wait=cfg.get('max_wait', 5.0, meaning='[s] longest wait for the flag to clear'),
        then=decision_param(cfg))


def make(s):
    topic, max_age, debounce, holdoff = s['topic'], s['max_age'], s['debounce'], s['holdoff']
    handler_args = dict(clear_time=s['clear_time'], max_wait=s['max_wait'], then=s['then'])
    trig = Trigger(KIND, None, None, debounce=debounce, holdoff=holdoff, priority=1, on_fire=publish_zero)
    watch = FlagWatch(topic, max_age, trig.notify)
    trig.condition = watch
    trig.handler = WaitClear(watch, **handler_args)
    return trig
