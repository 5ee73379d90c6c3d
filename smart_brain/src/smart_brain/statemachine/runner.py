"""Runner: executes a state (usually a whole machine) on one persistent thread.

start() marks the state running before it returns, so a preempt() right after start()
is never lost; wait() blocks with a monotonic timeout; the outcome (or the error the
state raised) is kept. One Runner = one thread for its whole life.
"""
import threading

from smart_brain.statemachine.userdata import UserData
from smart_brain.statemachine.workers import Worker


class Runner(object):
    def __init__(self, name='runner'):
        self._worker = None
        self._name = name
        self._lock = threading.Condition()
        self._busy = False
        self._state = None
        self.outcome = None
        self.error = None

    def start(self, state, userdata=None, on_done=None):
        with self._lock:
            if self._busy:
                raise RuntimeError('runner %s is already running %s' % (self._name, type(self._state).__name__))
            if self._worker is None:
                self._worker = Worker(self._name)
            self._busy = True
            self._state = state
            self.outcome = self.error = None
            state._begin()
        ud = userdata if userdata is not None else UserData()
        self._worker.submit(lambda: self._run(state, ud, on_done))

    def _run(self, state, ud, on_done):
        outcome = error = None
        try:
            outcome = state.run(ud)
        except Exception as e:
            error = e
        finally:
            state._end()
        with self._lock:
            self.outcome, self.error = outcome, error
            self._busy = False
            self._lock.notify_all()
        if on_done is not None:
            on_done(outcome, error)

    def preempt(self):
        with self._lock:
            state = self._state if self._busy else None
        return state.request_preempt() if state is not None else False

    def is_running(self):
        return self._busy

    def wait(self, timeout=None):
        """True when the state has ended (within `timeout` seconds)."""
        with self._lock:
            return self._lock.wait_for(lambda: not self._busy, timeout)
