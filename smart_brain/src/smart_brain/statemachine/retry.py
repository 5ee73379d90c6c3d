"""Retry: run a state again while it ends 'aborted', up to `attempts` times in all.

For the steps that must work ("score one point with the highest certainty"): a goal the
driver aborted (blocked, lost localization) is tried again before giving up.
"""
from smart_brain.statemachine.state import State


class Retry(State):
    def __init__(self, state, attempts=2, retry_on=('aborted',)):
        State.__init__(self, state.get_registered_outcomes(), state.get_registered_input_keys(),
                       state.get_registered_output_keys())
        self.state = state
        self.attempts = int(attempts)
        self._retry_on = tuple(retry_on)
        self.tries = 0

    def request_preempt(self):
        if not State.request_preempt(self):
            return False
        self.state.request_preempt()
        return True

    def progress(self):
        fn = getattr(self.state, 'progress', None)
        return fn() if callable(fn) else None

    def execute(self, ud):
        self.tries = 0
        while True:
            self.tries += 1
            self.state._begin()
            try:
                if self.preempt_requested():
                    return 'preempted' if 'preempted' in self._outcomes else self._retry_on[0]
                outcome = self.state.run(ud)
            finally:
                self.state._end()
            if outcome not in self._retry_on or self.tries >= self.attempts or self.preempt_requested():
                return outcome
