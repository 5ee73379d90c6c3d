"""MatchTimer: waits for the start signal, then counts the match on one clock and calls on_end
once at `duration`.

The clock is a function returning seconds:
- on the robot, `time.monotonic` (the default): a wall clock stepped by NTP, or a stalled
  /clock, can neither stretch nor cut a match;
- in simulation (use_sim_time), ROS time (the brain's clock, statemachine/clock.py), so a
  match lasts `duration` simulated seconds at any real-time factor. A simulated clock may stall (paused simulator:
  the match waits with it), run fast, or jump; the timer only ever moves forward: a clock that
  jumps back (a bag looping) does not give time back to the match.

The start signal is the HAL human-interface device's hal_nodes/HumanInput (`started` goes true
when the cord is pulled), or the brain's ~start service; with start 'immediate' the match
starts at once. One thread, started once. With a simulated clock it looks at the clock every
`poll` wall seconds (nothing wakes a thread on /clock); on the monotonic clock it sleeps until
the end.
"""
import threading
import time


class MatchTimer(object):
    def __init__(self, duration, on_start, on_end, clock=time.monotonic, poll=None):
        self.duration = float(duration)
        self._on_start = on_start
        self._on_end = on_end
        self._clock = clock
        self._poll = None if poll is None else float(poll)
        self._latest = None          # the newest clock reading: never goes back
        self._cond = threading.Condition()
        self._started_at = None
        self._ended = False
        self._thread = threading.Thread(target=self._run, name='match-timer', daemon=True)
        self._thread.start()

    def _now(self):
        t = self._clock()
        if self._latest is None or t > self._latest:
            self._latest = t
        return self._latest

    def start(self, at=None):
        """The start signal (idempotent): returns False if the match had already started.
        `at`: when the match started on this clock (a brain resuming a match after a restart);
        default now."""
        with self._cond:
            if self._started_at is not None:
                return False
            now = self._now()
            self._started_at = now if at is None else min(float(at), now)
            self._cond.notify_all()
        return True

    @property
    def started_at(self):
        """When the match started on this clock (None before the start signal)."""
        return self._started_at

    def end_now(self):
        """End the match at once (emergency or shutdown)."""
        with self._cond:
            now = self._now()
            if self._started_at is None:
                self._started_at = now - self.duration
            self.duration = min(self.duration, now - self._started_at)
            self._cond.notify_all()

    @property
    def started(self):
        return self._started_at is not None

    @property
    def ended(self):
        return self._ended

    def elapsed(self):
        with self._cond:
            if self._started_at is None:
                return 0.0
            return min(self.duration, self._now() - self._started_at) if self._ended else self._now() - self._started_at

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
                left = self.duration - (self._now() - self._started_at)
                if left <= 0:
                    break
                self._cond.wait(left if self._poll is None else min(left, self._poll))
        self._ended = True
        self._on_end()
