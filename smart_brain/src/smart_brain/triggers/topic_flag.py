"""topic_flag: a std_msgs/Bool topic says "stop" (a custom sensor, an operator, a test).

Config (~triggers/topic_flag): topic, max_age [s] (an old True no longer counts),
debounce, holdoff, clear_time, max_wait, then. Handler: as opponent_ahead (zero speed,
wait until clear, resume).
"""
import threading

from smart_brain.statemachine import clock
from smart_brain.actions.stop import publish_zero
from smart_brain.statemachine import Trigger
from smart_brain.triggers import Config, decision_param
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


def make(values):
    cfg = Config(KIND, values)
    topic = cfg.get('topic', '/brain/stop_flag', str)
    max_age = cfg.get('max_age', 1.0)
    debounce = cfg.get('debounce', 0.0)
    holdoff = cfg.get('holdoff', 0.5)
    handler_args = dict(clear_time=cfg.get('clear_time', 0.3), max_wait=cfg.get('max_wait', 5.0),
                        then=decision_param(cfg))
    cfg.done()
    trig = Trigger(KIND, None, None, debounce=debounce, holdoff=holdoff, priority=1, on_fire=publish_zero)
    watch = FlagWatch(topic, max_age, trig.notify)
    trig.condition = watch
    trig.handler = WaitClear(watch, **handler_args)
    return trig
