"""MonitorState: wait on a topic until a condition says stop (smach_ros's MonitorState).

    MonitorState('/mcl/quality', LocalizationQuality, lambda ud, msg: not msg.lost)

cond_cb(userdata, msg) returns True to keep watching; the first False gives 'invalid'.
After max_checks messages that all returned True the outcome is 'valid' (-1: no limit).
New here: `timeout` [s, monotonic] gives 'aborted' when nothing decided in time (a dead
topic cannot hang the machine), and a preempt gives 'preempted' at once.

`subscribe(topic, msg_type, callback) -> object with unregister()` defaults to
rospy.Subscriber; tests and non-ROS feeds pass their own.
"""
import threading

from smart_brain.statemachine.state import State


def _ros_subscribe(topic, msg_type, callback):
    import rospy
    return rospy.Subscriber(topic, msg_type, callback, queue_size=1)


class MonitorState(State):
    def __init__(self, topic, msg_type, cond_cb, max_checks=-1, timeout=None, input_keys=(), output_keys=(),
                 subscribe=None):
        State.__init__(self, ('valid', 'invalid', 'preempted', 'aborted'), input_keys, output_keys)
        self.topic = topic
        self._msg_type = msg_type
        self._cond_cb = cond_cb
        self._max_checks = max_checks
        self.timeout = timeout
        self._subscribe = subscribe or _ros_subscribe
        self._lock = threading.Lock()
        self._verdict = None
        self._checks = 0
        self._ud = None
        self._active = False
        self._error = None

    def _on_msg(self, msg):
        with self._lock:
            if self._verdict is not None or not self._active:
                return
            try:
                keep = self._cond_cb(self._ud, msg)
            except Exception as e:  # re-raised in execute(), in the machine's thread
                self._error = e
                self._verdict = 'error'
            else:
                self._checks += 1
                if not keep:
                    self._verdict = 'invalid'
                elif 0 <= self._max_checks <= self._checks:
                    self._verdict = 'valid'
        if self._verdict is not None:
            self.wake()

    def execute(self, ud):
        with self._lock:
            self._verdict, self._checks, self._ud, self._error, self._active = None, 0, ud, None, True
        sub = self._subscribe(self.topic, self._msg_type, self._on_msg)
        try:
            waited = self.wait(self.timeout, predicate=lambda: self._verdict is not None)
        finally:
            sub.unregister()
            with self._lock:
                self._ud, self._active = None, False
        if self._error is not None:
            raise self._error
        if waited == 'preempted':
            return 'preempted'
        if waited == 'timeout':
            return 'aborted'
        return self._verdict
