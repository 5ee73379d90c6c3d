"""BrainSlave: the original contract for long actions.

One action at a time, each with an ID: start(id, state) with the running ID does nothing;
a different ID preempts the running action (its goals are cancelled) and starts the new
one. current_id, elapsed() and progress() (0..100 %) are readable at any time. Works
without ROS; the brain publishes status() on /brain/action_status.
"""
import threading

from smart_brain.statemachine import Runner, clock


class BrainSlave(object):
    def __init__(self, stop_timeout=3.0):
        self._runner = Runner('brain-slave')
        self._lock = threading.Lock()
        self._stop_timeout = stop_timeout
        self.current_id = ''
        self._state = None
        self._started = None
        self._ended = None
        self.outcome = ''
        self.error = None

    def start(self, action_id, state, userdata=None):
        """'started', 'already running' or 'replaced <old id>'."""
        with self._lock:
            if self._runner.is_running() and action_id == self.current_id:
                return 'already running'
            replaced = ''
            if self._runner.is_running():
                replaced = self.current_id
                self._runner.preempt()
                if not self._runner.wait(self._stop_timeout):
                    raise RuntimeError('action %s did not stop within %.1f s' % (replaced, self._stop_timeout))
            self.current_id = action_id
            self._state = state
            self._started = clock.now()
            self._ended = None
            self.outcome, self.error = '', None
            self._runner.start(state, userdata, on_done=self._done)
            return 'replaced %s' % replaced if replaced else 'started'

    def _done(self, outcome, error):
        self._ended = clock.now()
        self.outcome = outcome or ''
        self.error = error

    def stop(self):
        """Preempt the running action and wait for it; True if it ended."""
        if self._runner.is_running():
            self._runner.preempt()
        return self._runner.wait(self._stop_timeout)

    def running(self):
        return self._runner.is_running()

    def elapsed(self):
        if self._started is None:
            return 0.0
        return (self._ended or clock.now()) - self._started

    def progress(self):
        """[%]: the action's own progress() if it has one (driver feedback), 100 once succeeded."""
        if self._state is None:
            return 0.0
        if not self._runner.is_running():
            return 100.0 if self.outcome == 'succeeded' else self._own_progress()
        return self._own_progress()

    def _own_progress(self):
        fn = getattr(self._state, 'progress', None)
        value = fn() if callable(fn) else None
        return max(0.0, min(100.0, float(value))) if value is not None else 0.0

    def status(self):
        """(id, state, elapsed, progress, outcome) with state: idle, running or the outcome."""
        if self._state is None:
            state = 'idle'
        elif self._runner.is_running():
            state = 'running'
        else:
            state = self.outcome or ('error' if self.error else 'idle')
        return self.current_id, state, self.elapsed(), self.progress(), self.outcome
