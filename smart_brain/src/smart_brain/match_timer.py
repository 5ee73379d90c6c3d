"""MatchTimer: waits for the start signal, then counts the match on the monotonic clock
(a stalled /clock cannot stretch a match) and calls on_end once at `duration`.

The start signal is the HAL human-interface device's hal_nodes/HumanInput (`started`
goes true when the cord is pulled) on `start_topic`, or the brain's ~start service; with
start 'immediate' the match starts at once. One thread, started once.
"""
import threading
import time


class MatchTimer(object):
    def __init__(self, duration, on_start, on_end):
        self.duration = float(duration)
        self._on_start = on_start
        self._on_end = on_end
        self._cond = threading.Condition()
        self._started_at = None
        self._ended = False
        self._thread = threading.Thread(target=self._run, name='match-timer', daemon=True)
        self._thread.start()

    def start(self):
        """The start signal (idempotent): returns False if the match had already started."""
        with self._cond:
            if self._started_at is not None:
                return False
            self._started_at = time.monotonic()
            self._cond.notify_all()
        return True

    def end_now(self):
        """End the match at once (emergency or shutdown)."""
        with self._cond:
            if self._started_at is None:
                self._started_at = time.monotonic() - self.duration
            self.duration = min(self.duration, time.monotonic() - self._started_at)
            self._cond.notify_all()

    @property
    def started(self):
        return self._started_at is not None

    @property
    def ended(self):
        return self._ended

    def elapsed(self):
        return 0.0 if self._started_at is None else time.monotonic() - self._started_at

    def remaining(self):
        if self._ended:
            return 0.0
        return self.duration if self._started_at is None else max(0.0, self.duration - self.elapsed())

    def wait_started(self, timeout=None):
        with self._cond:
            return self._cond.wait_for(lambda: self._started_at is not None, timeout)

    def _run(self):
        with self._cond:
            self._cond.wait_for(lambda: self._started_at is not None)
        self._on_start()
        with self._cond:
            while True:
                left = self._started_at + self.duration - time.monotonic()
                if left <= 0:
                    break
                self._cond.wait(left)
        self._ended = True
        self._on_end()
