"""StateMachine: children joined by transitions from their outcomes, as in smach.

    sm = StateMachine(outcomes=['succeeded', 'aborted', 'preempted'])
    with sm:
        StateMachine.add('DRIVE', drive, transitions={'succeeded': 'GRAB', 'aborted': 'aborted',
                         'preempted': 'preempted'}, remapping={'goal': 'target'}, timeout=8.0)

Beyond smach: `timeout` [s, monotonic] on add(): when a child overruns it is preempted
(an action state cancels its goal) and its outcome becomes 'aborted', which must then have
a transition; and a history of where the last run was preempted, so a supervisor can
resume there (resume_next) or restart anywhere (restart_next).
"""
import logging

from smart_brain.statemachine import timers
from smart_brain.statemachine.container import Container, classorinstancemethod
from smart_brain.statemachine.errors import InvalidStateError, InvalidTransitionError
from smart_brain.statemachine.state import State
from smart_brain.statemachine.userdata import Remapper

log = logging.getLogger('smart_brain.statemachine')


class StateMachine(Container):
    def __init__(self, outcomes, input_keys=(), output_keys=(), io_keys=()):
        Container.__init__(self, outcomes, input_keys, output_keys, io_keys)
        self._transitions = {}    # label -> {outcome: target}
        self._remappings = {}     # label -> {child key: my key}
        self._timeouts = {}       # label -> seconds
        self._initial = None
        self._current = None      # label running now
        self._history = None      # label that was running when the last run was preempted
        self._start_at = None     # label the next run starts at (history / restart)
        self._resume_child = False
        self._timed_out = False
        self._run_token = None

    def _add_impl(self, label, state, transitions=None, remapping=None, timeout=None):
        """Add a child; the first one added is the initial state."""
        with self._lock:
            self._add_child(label, state)
            transitions = dict(transitions or {})
            if timeout is not None:
                if timeout <= 0:
                    raise InvalidStateError('state %s: timeout must be > 0, got %r' % (label, timeout))
                if 'aborted' not in transitions:
                    raise InvalidTransitionError("state %s has a timeout, so its outcome 'aborted' needs a transition" % label)
                self._timeouts[label] = float(timeout)
            self._transitions[label] = transitions
            self._remappings[label] = dict(remapping or {})
            if self._initial is None:
                self._initial = label
        return state

    add = classorinstancemethod(_add_impl)

    def set_initial_state(self, labels, userdata=None):
        """smach-compatible: the next run starts at labels[0]; userdata entries are merged in."""
        label = labels[0] if isinstance(labels, (list, tuple)) else labels
        if label not in self._children:
            raise InvalidStateError("initial state '%s' is not a state of this machine" % label)
        self._initial = label
        if userdata is not None:
            self.userdata.update(userdata)

    def check_consistency(self):
        if not self._children:
            raise InvalidStateError('state machine has no states')
        for label, state in self._children.items():
            trans = self._transitions[label]
            outcomes = set(state.get_registered_outcomes())
            if label in self._timeouts:
                outcomes.add('aborted')
            for outcome in sorted(outcomes):
                target = trans.get(outcome)
                if target is None:
                    raise InvalidTransitionError("state %s: outcome '%s' has no transition (targets: states %s or outcomes %s)"
                                                 % (label, outcome, ', '.join(self._children), ', '.join(self._outcomes)))
            for outcome, target in trans.items():
                if outcome not in outcomes:
                    raise InvalidTransitionError("state %s has no outcome '%s' (outcomes: %s)" % (label, outcome, ', '.join(sorted(outcomes))))
                if target not in self._children and target not in self._outcomes:
                    raise InvalidTransitionError("state %s: outcome '%s' goes to '%s', which is neither a state nor an outcome"
                                                 % (label, outcome, target))
            if isinstance(state, Container):
                state.check_consistency()

    # ---- introspection ----
    def get_active_states(self):
        cur = self._current
        return [cur] if cur is not None else []

    def get_initial_states(self):
        return [self._initial] if self._initial else []

    def get_internal_edges(self):
        return [(o, label, t) for label, trans in self._transitions.items() for o, t in trans.items()]

    # ---- history ----
    def resume_next(self):
        with self._lock:
            if self._history is not None:
                self._start_at = self._history
                self._resume_child = True
                child = self._children[self._history]
                if isinstance(child, Container):
                    child.resume_next()

    def restart_next(self, label=None):
        with self._lock:
            if label is not None and label not in self._children:
                raise InvalidStateError("no state '%s' to restart at (states: %s)" % (label, ', '.join(self._children)))
            self._start_at = label
            self._resume_child = False
            self._history = None

    def history(self):
        return self._history

    # ---- execution ----
    def request_preempt(self):
        # Our flag and the active child's, under our lock: the child we forward to is the
        # one marked running, never one that has not started yet.
        with self._lock:
            if not State.request_preempt(self):
                return False
            cur = self._current
            if cur is not None:
                self._children[cur].request_preempt()
        return True

    def _on_timeout(self, label, token):
        with self._lock:
            if self._current == label and self._run_token is token:
                log.warning('state %s overran its timeout of %.2f s: preempting it, outcome aborted', label, self._timeouts[label])
                self._timed_out = True
                self._children[label].request_preempt()

    def _execute_container(self):
        self.check_consistency()
        with self._lock:
            label = self._start_at or self._initial
            self._start_at = None
            resumed = self._resume_child
            self._resume_child = False
        self._notify(self._start_cbs, [label])
        if resumed:
            log.info('resuming at %s', label)
        while True:
            state = self._children[label]
            token = object()
            with self._lock:
                if self.preempt_requested():
                    # Preempted between two states: nothing to forward to, we consume it.
                    self.service_preempt()
                    self._history = label
                    self._current = None
                    return self._finish('preempted' if 'preempted' in self._outcomes else None, label)
                self._current = label
                self._run_token = token
                self._timed_out = False
                state._begin()   # marked running inside our lock: a preempt now reaches it
            self._notify(self._transition_cbs, [label])
            timer = None
            if label in self._timeouts:
                timer = timers.call_later(self._timeouts[label], lambda l=label, t=token: self._on_timeout(l, t))
            try:
                ud = Remapper(self.userdata, state.get_registered_input_keys(), state.get_registered_output_keys(),
                              self._remappings[label])
                outcome = state.run(ud)
            finally:
                if timer is not None:
                    timer.cancel()
                state._end()
            with self._lock:
                if self._timed_out:
                    outcome = 'aborted'
                self._current = None
                preempted = self.service_preempt()
                if preempted:
                    self._history = label
                    if outcome != 'preempted' and 'preempted' in self._outcomes:
                        # A late request: the child finished anyway; the machine stops here.
                        return self._finish('preempted', label)
                elif outcome != 'preempted':
                    self._history = None
                else:
                    self._history = label
            target = self._transitions[label][outcome]
            if target in self._outcomes and target not in self._children:
                return self._finish(target, label)
            label = target

    def _finish(self, outcome, last_label):
        if outcome is None:
            outcome = self._transitions[last_label].get('preempted') or self._outcomes[0]
        self._notify(self._transition_cbs, [])
        self._notify(self._termination_cbs, [last_label], outcome)
        return outcome
