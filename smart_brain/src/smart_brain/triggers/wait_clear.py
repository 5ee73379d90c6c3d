"""WaitClear: the common handler: stop the wheels, wait until the trigger's condition has
been false for `clear_time`, then 'resume'; if it is still true after `max_wait`, give
the configured decision instead (resume / restart / aborted / a state label)."""

from smart_brain.actions.stop import publish_zero
from smart_brain.statemachine import State, clock


class WaitClear(State):
    def __init__(self, condition, clear_time=0.5, max_wait=3.0, then='resume', stop=True):
        State.__init__(self, outcomes=['resume', then, 'preempted'])
        self._condition = condition
        self.clear_time = clear_time
        self.max_wait = max_wait
        self.then = then
        self.stop = stop

    def execute(self, ud):
        if self.stop:
            publish_zero()
        start = clock.now()
        clear_since = None
        while True:
            now = clock.now()
            if self._condition():
                clear_since = None
            elif clear_since is None:
                clear_since = now
            if clear_since is not None and now - clear_since >= self.clear_time:
                return 'resume'
            if now - start >= self.max_wait:
                return self.then
            if self.wait(0.02) == 'preempted':
                return 'preempted'
