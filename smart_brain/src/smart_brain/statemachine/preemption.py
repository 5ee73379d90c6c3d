"""A state's preempt request: set by anyone, consumed exactly once.

smach kept a bare flag per state, so a request that arrived while a state was finishing
was either lost or stayed "sticky" and preempted the next run. Here a request only counts
while its state is running (State.request_preempt drops it otherwise), containers forward
it under their own lock to the child they have already marked running, and the flag is
cleared when the run ends: whoever returns 'preempted' (the child or, for a late request,
its container) is the one consumer.

The same condition variable wakes states that wait for something else too (a message, a
goal's end), so a preempt interrupts every wait at once.
"""
import threading

from smart_brain.statemachine import clock


class Preemption(object):
    def __init__(self):
        self._cond = threading.Condition(threading.Lock())
        self._requested = False

    def request(self):
        with self._cond:
            self._requested = True
            self._cond.notify_all()

    def requested(self):
        return self._requested

    def consume(self):
        """True once per request: the caller now owns the preempt."""
        with self._cond:
            was = self._requested
            self._requested = False
            return was

    def clear(self):
        with self._cond:
            self._requested = False

    def notify(self):
        """Wake waiters to re-check their predicate (a message arrived, a goal ended)."""
        with self._cond:
            self._cond.notify_all()

    def wait(self, timeout=None, predicate=None):
        """Wait until preempted, predicate() is true, or `timeout` seconds pass on the brain's clock.

        Returns 'preempted', 'ready' or 'timeout'. The predicate is checked under the lock,
        so a notify() that follows a change it looks at cannot be missed.
        """
        deadline = None if timeout is None else clock.now() + timeout
        with self._cond:
            while True:
                if self._requested:
                    return 'preempted'
                if predicate is not None and predicate():
                    return 'ready'
                if deadline is None:
                    self._cond.wait(1.0)
                else:
                    left = deadline - clock.now()
                    if left <= 0:
                        return 'timeout'
                    self._cond.wait(min(clock.wall_slice(left), 1.0))
