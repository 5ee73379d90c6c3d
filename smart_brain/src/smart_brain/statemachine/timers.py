"""One shared timer thread for every deadline in the process (state timeouts, periodic
introspection), so entering a state never creates a thread. Deadlines are on the brain's
clock (clock.py: monotonic on the robot, ROS time in simulation)."""
import heapq
import itertools
import threading

from smart_brain.statemachine import clock


class TimerHandle(object):
    __slots__ = ('cancelled',)

    def __init__(self):
        self.cancelled = False

    def cancel(self):
        self.cancelled = True


class _TimerThread(object):
    def __init__(self):
        self._cond = threading.Condition()
        self._heap = []
        self._seq = itertools.count()
        self._thread = None

    def call_later(self, delay, fn):
        handle = TimerHandle()
        with self._cond:
            heapq.heappush(self._heap, (clock.now() + max(0.0, delay), next(self._seq), handle, fn))
            if self._thread is None:
                self._thread = threading.Thread(target=self._run, name='statemachine-timers', daemon=True)
                self._thread.start()
            self._cond.notify()
        return handle

    def _run(self):
        while True:
            with self._cond:
                while not self._heap or self._heap[0][0] > clock.now():
                    self._cond.wait(None if not self._heap else clock.wall_slice(self._heap[0][0] - clock.now()))
                _, _, handle, fn = heapq.heappop(self._heap)
            if not handle.cancelled:
                try:
                    fn()
                except Exception:  # a timer callback must never kill the shared thread
                    import traceback
                    traceback.print_exc()


_TIMERS = _TimerThread()


def call_later(delay, fn):
    """Call fn() after `delay` seconds on the shared timer thread; returns a handle with cancel()."""
    return _TIMERS.call_later(delay, fn)
