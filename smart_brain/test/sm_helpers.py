"""Small states and a scripted action server for the library tests (test code only)."""
import threading
import time

from smart_brain.statemachine import State, goal_status


class Counter(State):
    """Counts its runs, returns a fixed outcome."""

    def __init__(self, outcome='done', extra=()):
        State.__init__(self, outcomes=[outcome, 'preempted'] + list(extra))
        self.outcome = outcome
        self.runs = 0

    def execute(self, ud):
        self.runs += 1
        return self.outcome


class Sleeper(State):
    """Sleeps `duration` unless preempted; counts runs and preempts."""

    def __init__(self, duration=10.0):
        State.__init__(self, outcomes=['done', 'preempted'])
        self.duration = duration
        self.runs = 0
        self.preempted = 0
        self.started = threading.Event()

    def execute(self, ud):
        self.runs += 1
        self.started.set()
        if self.wait(self.duration) == 'preempted':
            self.preempted += 1
            self.service_preempt()
            return 'preempted'
        return 'done'


class Stubborn(State):
    """Ignores preempts: always sleeps its full time and says 'done'."""

    def __init__(self, duration):
        State.__init__(self, outcomes=['done', 'preempted'])
        self.duration = duration
        self.started = threading.Event()

    def execute(self, ud):
        self.started.set()
        time.sleep(self.duration)
        return 'done'


class ScriptedGoal(object):
    def __init__(self, server, goal, on_change, on_feedback):
        self.server, self.goal = server, goal
        self._on_change, self._on_feedback = on_change, on_feedback
        self._status = goal_status.PENDING
        self._done = False
        self.cancels = 0
        self.forgotten = False

    def finish(self, status, result='result'):
        self._status = status
        self._result = result
        self._done = status in goal_status.TERMINAL
        self._on_change()

    def done(self):
        return self._done

    def status(self):
        return self._status

    def result(self):
        return getattr(self, '_result', None)

    def cancel(self):
        self.cancels += 1
        if self._done:
            return
        if self.server.confirm_cancel:
            self.finish(goal_status.PREEMPTED if self._status == goal_status.ACTIVE else goal_status.RECALLED)
        else:
            self._status = goal_status.PREEMPTING

    def forget(self):
        self.forgotten = True


class ScriptedServer(object):
    """An action client/server pair in one object: goals end as the test says."""

    def __init__(self, ready=True, confirm_cancel=True, auto=None, delay=0.0):
        self.ready = ready
        self.confirm_cancel = confirm_cancel
        self.auto = auto        # status to finish every goal with after `delay`
        self.delay = delay
        self.goals = []

    def server_ready(self):
        return self.ready

    def send(self, goal, on_change, on_feedback):
        g = ScriptedGoal(self, goal, on_change, on_feedback)
        self.goals.append(g)
        g.finish(goal_status.ACTIVE)
        if self.auto is not None:
            def later():
                time.sleep(self.delay)
                if not g.done():
                    g.finish(self.auto)
            threading.Thread(target=later, daemon=True).start()
        return g


class SimClock(object):
    """A simulated clock the test moves by hand (set, advance): it can jump, stall and run fast."""

    def __init__(self, t=100.0):
        self.t = t
        self.lock = threading.Lock()

    def __call__(self):
        with self.lock:
            return self.t

    def set(self, t):
        with self.lock:
            self.t = t

    def advance(self, dt):
        with self.lock:
            self.t += dt
