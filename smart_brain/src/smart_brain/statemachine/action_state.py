"""ActionState: send an actionlib goal, map its end to an outcome (smach_ros's SimpleActionState).

    DRIVE = ActionState('/hal/driver/goto', GotoAction, goal_key='target', result_key='report',
                        exec_timeout=10.0)

Outcomes: 'succeeded', 'aborted', 'preempted' plus any extra `outcomes` a result_cb may
return. Every actionlib status is mapped (goal_status.py). The goal is never left
running: a preempt cancels it and waits (monotonic, `preempt_timeout`) for the server to
confirm; every other exit path cancels it too. Waits never hang: no server within
`server_wait_timeout`, no result within `exec_timeout`, no confirmation of a cancel:
each gives 'aborted' after an explicit cancel. Goals go through the GoalGuard, so the
match end cancels them and refuses new ones.

`client` (for tests or other transports) is any object with server_ready() and
send(goal, on_change, on_feedback) -> goal handle with done(), status(), result(),
cancel(), forget(); by default a RosActionClient is made on first use.
"""
import logging
import threading

from smart_brain.statemachine import clock
from smart_brain.statemachine import goal_status
from smart_brain.statemachine.goal_guard import GOAL_GUARD
from smart_brain.statemachine.state import State

log = logging.getLogger('smart_brain.statemachine')


class ActionState(State):
    def __init__(self, action_name, action_spec=None, goal=None, goal_key=None, goal_slots=(), goal_cb=None,
                 result_key=None, result_slots=(), result_cb=None, feedback_cb=None,
                 input_keys=(), output_keys=(), outcomes=(), server_wait_timeout=5.0, exec_timeout=None,
                 preempt_timeout=2.0, status_outcomes=None, client=None, guard=None):
        inputs = set(input_keys) | set(goal_slots) | ({goal_key} if goal_key else set())
        outputs = set(output_keys) | set(result_slots) | ({result_key} if result_key else set())
        State.__init__(self, ['succeeded', 'aborted', 'preempted'] + list(outcomes), inputs, outputs)
        if goal is None and goal_key is None and action_spec is None:
            raise ValueError('ActionState %s: give goal, goal_key or action_spec' % action_name)
        self.action_name = action_name
        self._spec = action_spec
        self._goal = goal
        self._goal_key = goal_key
        self._goal_slots = tuple(goal_slots)
        self._goal_cb = goal_cb
        self._result_key = result_key
        self._result_slots = tuple(result_slots)
        self._result_cb = result_cb
        self._feedback_cb = feedback_cb
        self.server_wait_timeout = server_wait_timeout
        self.exec_timeout = exec_timeout
        self.preempt_timeout = preempt_timeout
        self._status_outcomes = status_outcomes
        self._client = client
        self._guard = guard if guard is not None else GOAL_GUARD
        self._changed = threading.Event()
        self._handle = None
        self._guard_cancelled = False
        #: the last status, feedback and why the state ended (for logs, progress and tests)
        self.status = None
        self.feedback = None
        self.end_reason = ''

    def _make_client(self):
        if self._client is None:
            from smart_brain.statemachine.ros_action_client import RosActionClient
            self._client = RosActionClient(self.action_name, self._spec)
        return self._client

    def _build_goal(self, ud):
        if self._goal_key is not None:
            goal = ud[self._goal_key]
        elif self._goal is not None:
            goal = self._goal
        else:
            goal = self._spec().action_goal.goal
        for slot in self._goal_slots:
            setattr(goal, slot, ud[slot])
        if self._goal_cb is not None:
            new = self._goal_cb(ud, goal)
            if new is not None:
                goal = new
        return goal

    def progress(self):
        """[%] from the last feedback's `progress` field (every driver action has one), else None."""
        return getattr(self.feedback, 'progress', None)

    def on_preempt_requested(self):
        self._changed.set()

    def _wait_server(self, client):
        deadline = clock.now() + self.server_wait_timeout
        while not client.server_ready():
            if self.preempt_requested():
                return 'preempted'
            if clock.now() > deadline:
                return 'timeout'
            self._changed.wait(0.02)
        return 'ready'

    def _ended(self, reason, outcome):
        self.end_reason = reason
        return outcome

    def execute(self, ud):
        self.status = self.feedback = None
        self._changed.clear()
        client = self._make_client()
        waited = self._wait_server(client)
        if waited == 'preempted':
            return self._ended('preempted before the server was ready', 'preempted')
        if waited == 'timeout':
            log.error('action %s: no server after %.1f s: aborted', self.action_name, self.server_wait_timeout)
            return self._ended('no server', 'aborted')
        goal = self._build_goal(ud)
        holder = {}
        self._guard_cancelled = False

        def guard_cancel():
            self._guard_cancelled = True
            if 'h' in holder:
                holder['h'].cancel()
            self._changed.set()
        guard_id = self._guard.admit(guard_cancel)
        if guard_id is None:
            log.warning('action %s: goal refused (%s)', self.action_name, self._guard.reason)
            return self._ended('refused: ' + self._guard.reason, 'aborted')
        try:
            if self.preempt_requested():
                return self._ended('preempted before sending', 'preempted')
            handle = holder['h'] = client.send(goal, self._changed.set, lambda fb: self._on_feedback(ud, fb))
            return self._follow(ud, handle)
        finally:
            h = holder.get('h')
            if h is not None and not h.done():
                h.cancel()       # any exit path: never leave the goal running
            self._guard.release(guard_id)

    def _on_feedback(self, ud, feedback):
        self.feedback = feedback
        if self._feedback_cb is not None:
            self._feedback_cb(ud, feedback)

    def _follow(self, ud, handle):
        started = clock.now()
        cancelled_at = None
        reason = None
        while not handle.done():
            now = clock.now()
            if cancelled_at is None:
                if self.preempt_requested():
                    reason = 'preempted'
                elif self._guard_cancelled:
                    reason = 'guard closed'
                elif self.exec_timeout is not None and now - started > self.exec_timeout:
                    reason = 'timeout'
                    log.error('action %s: no result within %.1f s: cancelling, aborted', self.action_name, self.exec_timeout)
                if reason is not None:
                    handle.cancel()
                    cancelled_at = now
            elif now - cancelled_at > self.preempt_timeout:
                log.error('action %s: server did not confirm the cancel within %.1f s (status %s)',
                          self.action_name, self.preempt_timeout, goal_status.name(handle.status()))
                handle.cancel()
                handle.forget()
                self.status = handle.status()
                return self._ended('cancel not confirmed', 'preempted' if reason == 'preempted' else 'aborted')
            self._changed.wait(0.05)
            self._changed.clear()
        self.status = status = handle.status()
        result = handle.result()
        if self._result_key is not None:
            ud[self._result_key] = result
        for slot in self._result_slots:
            if result is not None:
                ud[slot] = getattr(result, slot)
        outcome = goal_status.outcome_for(status, self._status_outcomes)
        if self._result_cb is not None:
            custom = self._result_cb(ud, status, result)
            if custom is not None:
                outcome = custom
        if self._guard_cancelled:
            reason = 'guard closed'
        if reason == 'timeout' or reason == 'guard closed':
            outcome = 'aborted'
        elif reason == 'preempted' and outcome != 'succeeded':
            outcome = 'preempted'
        return self._ended('status %s%s' % (goal_status.name(status), ' after ' + reason if reason else ''), outcome)
