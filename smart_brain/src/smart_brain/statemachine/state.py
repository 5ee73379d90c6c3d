"""State: a unit of behaviour that returns one of its named outcomes.

Subclass it and implement execute(userdata), as in smach. A long execute() must watch
preempt_requested() (or wait with self.wait(...), which a preempt interrupts) and then
return 'preempted' promptly.
"""
import threading

from smart_brain.statemachine.errors import InvalidOutcomeError, InvalidUserCodeError, StateMachineError
from smart_brain.statemachine.preemption import Preemption


class State(object):
    def __init__(self, outcomes=(), input_keys=(), output_keys=(), io_keys=()):
        self._outcomes = list(dict.fromkeys(outcomes))
        self._input_keys = set(input_keys) | set(io_keys)
        self._output_keys = set(output_keys) | set(io_keys)
        self._preemption = Preemption()
        self._run_lock = threading.Lock()
        self._running = False

    # ---- what a subclass implements ----
    def execute(self, userdata):
        raise NotImplementedError('%s.execute() is not implemented' % type(self).__name__)

    # ---- declared interface ----
    def register_outcomes(self, outcomes):
        for o in outcomes:
            if o not in self._outcomes:
                self._outcomes.append(o)

    def register_input_keys(self, keys):
        self._input_keys |= set(keys)

    def register_output_keys(self, keys):
        self._output_keys |= set(keys)

    def register_io_keys(self, keys):
        self.register_input_keys(keys)
        self.register_output_keys(keys)

    def get_registered_outcomes(self):
        return tuple(self._outcomes)

    def get_registered_input_keys(self):
        return tuple(sorted(self._input_keys))

    def get_registered_output_keys(self):
        return tuple(sorted(self._output_keys))

    # ---- preemption (see preemption.py for the rules) ----
    def request_preempt(self):
        """Ask the running state to stop; returns False (and drops the request) if it is not running."""
        with self._run_lock:
            if not self._running:
                return False
            self._preemption.request()
        self.on_preempt_requested()
        return True

    def on_preempt_requested(self):
        """Hook called (in the requester's thread) right after a request: act at once here if a wait cannot."""

    def preempt_requested(self):
        return self._preemption.requested()

    def service_preempt(self):
        """Acknowledge the request (smach name); returns whether there was one."""
        return self._preemption.consume()

    def recall_preempt(self):
        self._preemption.clear()

    def wait(self, timeout=None, predicate=None):
        """Sleep until preempted, predicate() holds or timeout [s]: 'preempted' | 'ready' | 'timeout'."""
        return self._preemption.wait(timeout, predicate)

    def wake(self):
        """Make a wait() re-check its predicate."""
        self._preemption.notify()

    def is_running(self):
        return self._running

    # ---- run protocol used by containers and runners ----
    def _begin(self):
        """Mark running (so preempts count); False if it already was."""
        with self._run_lock:
            if self._running:
                return False
            self._running = True
            self._preemption.clear()
            return True

    def _end(self):
        with self._run_lock:
            self._running = False
            self._preemption.clear()

    def run(self, userdata):
        """execute() under the run protocol, checking the outcome; what containers call."""
        began = self._begin()
        try:
            try:
                outcome = self.execute(userdata)
            except StateMachineError:
                raise
            except Exception as e:
                raise InvalidUserCodeError('%s.execute() raised %s: %s' % (type(self).__name__, type(e).__name__, e)) from e
        finally:
            if began:
                self._end()
        if outcome not in self._outcomes:
            raise InvalidOutcomeError("%s returned outcome %r; declared outcomes: %s"
                                      % (type(self).__name__, outcome, ', '.join(self._outcomes)))
        return outcome


class CBState(State):
    """A state from a function cb(userdata, *args) -> outcome (smach's CBState)."""

    def __init__(self, cb, outcomes=(), input_keys=(), output_keys=(), io_keys=(), cb_args=(), cb_kwargs=None):
        State.__init__(self, outcomes, input_keys, output_keys, io_keys)
        self._cb = cb
        self._args = tuple(cb_args)
        self._kwargs = dict(cb_kwargs or {})

    def execute(self, userdata):
        return self._cb(userdata, *self._args, **self._kwargs)


class WaitState(State):
    """Wait `duration` seconds on the brain's clock: 'succeeded', or 'preempted' at once when asked."""

    def __init__(self, duration):
        State.__init__(self, outcomes=('succeeded', 'preempted'))
        self.duration = float(duration)

    def execute(self, userdata):
        return 'preempted' if self.wait(self.duration) == 'preempted' else 'succeeded'
