"""localization_lost: /mcl/quality says lost, or its probability is below `min_probability`.
Handler: stop, then (spin: true) turn slowly on the spot so the beacons and the compass
are seen from every side, while watching /mcl/quality; resume once it is trusted again,
else the configured decision after `max_wait`.

Config: ~triggers/localization_lost, each key described where read() reads it (smart_brain/PARAMETERS.md).
"""
from smart_brain.actions.stop import StopState
from smart_brain.statemachine import Concurrence, MonitorState, StateMachine, Trigger
from smart_brain.triggers import decision_param

KIND = 'localization_lost'


class QualityWatch(object):
    def __init__(self, min_probability, notify):
        import rospy
        from hal_nodes.msg import LocalizationQuality
        self.min_probability = min_probability
        self._bad = False
        self._notify = notify
        self._sub = rospy.Subscriber('/mcl/quality', LocalizationQuality, self._on_msg, queue_size=1)

    def bad(self, msg):
        return msg.lost or msg.probability < self.min_probability

    def _on_msg(self, msg):
        self._bad = self.bad(msg)
        if self._bad:
            self._notify()

    def __call__(self):
        return self._bad


def read(cfg):
    return dict(
        min_probability=cfg.get('min_probability', 0.5, meaning="below this /mcl/quality probability the robot is lost "
                                "(the driver's ~min_probability)"),
        debounce=cfg.get('debounce', 0.5, meaning='[s] lost this long before it fires'),
        holdoff=cfg.get('holdoff', 2.0, meaning='[s] after its handler ends, it does not fire again for this long'),
        spin=cfg.get('spin', True, bool, meaning='turn slowly on the spot while waiting, so every beacon is seen'),
        max_wait=cfg.get('max_wait', 8.0, meaning='[s] longest wait for the localization to be trusted again'),
        then=decision_param(cfg))


def make(s):
    import math
    from hal_nodes.msg import LocalizationQuality
    from smart_brain.actions.rotate_by import rotate_by
    min_probability, debounce, holdoff, spin, max_wait, then = (
        s['min_probability'], s['debounce'], s['holdoff'], s['spin'], s['max_wait'], s['then'])
    trig = Trigger(KIND, None, None, debounce=debounce, holdoff=holdoff, priority=1)
    watch = QualityWatch(min_probability, trig.notify)
    trig.condition = watch
    # 'invalid' = the condition said stop watching: the quality is good again.
    recovered = MonitorState('/mcl/quality', LocalizationQuality, lambda ud, msg: watch.bad(msg), timeout=max_wait)
    relocalize = Concurrence(outcomes=['recovered', 'timeout', 'preempted'], default_outcome='timeout',
                             outcome_map={'recovered': {'WATCH': 'invalid'}},
                             child_termination_cb=lambda res: 'WATCH' in res)
    relocalize.add('WATCH', recovered)
    if spin:
        relocalize.add('SPIN', rotate_by(2 * math.pi, max_speed=0.5, exec_timeout=max_wait))
    handler = StateMachine(outcomes=sorted({'resume', then, 'preempted'}))
    handler.add('STOP', StopState(), transitions={'succeeded': 'RELOCALIZE'})
    handler.add('RELOCALIZE', relocalize, transitions={'recovered': 'resume', 'timeout': then, 'preempted': 'preempted'})
    trig.handler = handler
    return trig
