"""Concurrence: children run at the same time; their outcomes map to the container's.

As in smach:
    cc = Concurrence(outcomes=['found', 'timeout', 'preempted'], default_outcome='timeout',
                     outcome_map={'found': {'LOOK': 'found'}},
                     child_termination_cb=lambda outcomes: outcomes.get('LOOK') == 'found')
outcome_map entries are checked in order once every child has ended; the first whose
children all ended with the listed outcomes wins, else outcome_cb(outcomes), else
default_outcome. child_termination_cb(outcomes so far) returning True preempts the
children still running.

Differences from smach: the children run on workers owned by the Concurrence for its
whole life (no thread per child per entry); a preempt of the Concurrence always ends it
with 'preempted' (smach could report a child's outcome instead); a child raising ends the
others (preempted) and the error is re-raised in the caller.
"""
import threading

from smart_brain.statemachine.container import Container, classorinstancemethod
from smart_brain.statemachine.errors import InvalidTransitionError
from smart_brain.statemachine.state import State
from smart_brain.statemachine.userdata import Remapper
from smart_brain.statemachine.workers import WorkerPool


class Concurrence(Container):
    def __init__(self, outcomes, default_outcome, input_keys=(), output_keys=(), io_keys=(),
                 outcome_map=None, outcome_cb=None, child_termination_cb=None):
        Container.__init__(self, outcomes, input_keys, output_keys, io_keys)
        if default_outcome not in self._outcomes:
            raise InvalidTransitionError("default_outcome '%s' is not one of %s" % (default_outcome, ', '.join(self._outcomes)))
        self._default = default_outcome
        self._outcome_map = list((outcome_map or {}).items())
        self._outcome_cb = outcome_cb
        self._termination_cb = child_termination_cb
        self._remappings = {}
        self._pool = WorkerPool('concurrence')
        self._done = threading.Condition(self._lock)
        self._results = {}
        self._errors = []
        self._active = set()

    @classorinstancemethod
    def add(self, label, state, remapping=None):
        with self._lock:
            self._add_child(label, state)
            self._remappings[label] = dict(remapping or {})
        return state

    def check_consistency(self):
        for outcome, children in self._outcome_map:
            if outcome not in self._outcomes:
                raise InvalidTransitionError("outcome_map key '%s' is not an outcome of the Concurrence (%s)" % (outcome, ', '.join(self._outcomes)))
            for label, child_outcome in children.items():
                if label not in self._children:
                    raise InvalidTransitionError("outcome_map '%s' names unknown child '%s'" % (outcome, label))
                if child_outcome not in self._children[label].get_registered_outcomes():
                    raise InvalidTransitionError("outcome_map '%s': child %s has no outcome '%s'" % (outcome, label, child_outcome))
        for state in self._children.values():
            if isinstance(state, Container):
                state.check_consistency()

    def get_active_states(self):
        with self._lock:
            return sorted(self._active)

    def get_initial_states(self):
        return list(self._children)

    def get_internal_edges(self):
        edges = []
        for outcome, children in self._outcome_map:
            for label, child_outcome in children.items():
                edges.append((child_outcome, label, outcome))
        return edges

    def resume_next(self):
        for state in self._children.values():
            if isinstance(state, Container):
                state.resume_next()

    def request_preempt(self):
        with self._lock:
            if not State.request_preempt(self):
                return False
            for label in self._active:
                self._children[label].request_preempt()
        return True

    def _run_child(self, label, state):
        outcome = error = None
        try:
            ud = Remapper(self.userdata, state.get_registered_input_keys(), state.get_registered_output_keys(),
                          self._remappings[label])
            outcome = state.run(ud)
        except Exception as e:  # handed to the caller's thread
            error = e
        finally:
            state._end()
        with self._lock:
            self._active.discard(label)
            self._results[label] = outcome
            if error is not None:
                self._errors.append(error)
            stop = error is not None
            if not stop and self._termination_cb is not None:
                try:
                    stop = bool(self._termination_cb(dict(self._results)))
                except Exception as e:
                    self._errors.append(e)
                    stop = True
            if stop:
                for other in self._active:
                    self._children[other].request_preempt()
            self._done.notify_all()
        self._notify(self._transition_cbs, self.get_active_states())

    def _execute_container(self):
        self.check_consistency()
        children = list(self._children.items())
        workers = self._pool.workers(len(children))
        with self._lock:
            self._results = {}
            self._errors = []
            self._active = set()
            if self.preempt_requested():
                self.service_preempt()
                return 'preempted' if 'preempted' in self._outcomes else self._default
            for label, state in children:
                state._begin()
                self._active.add(label)
        self._notify(self._start_cbs, list(self._children))
        self._notify(self._transition_cbs, self.get_active_states())
        for worker, (label, state) in zip(workers, children):
            worker.submit(lambda l=label, s=state: self._run_child(l, s))
        with self._lock:
            while len(self._results) < len(children):
                self._done.wait()
            results = dict(self._results)
            preempted = self.service_preempt()
            errors = list(self._errors)
        if errors:
            raise errors[0]
        if preempted and 'preempted' in self._outcomes:
            outcome = 'preempted'
        else:
            outcome = None
            for candidate, wanted in self._outcome_map:
                if all(results.get(label) == o for label, o in wanted.items()):
                    outcome = candidate
                    break
            if outcome is None and self._outcome_cb is not None:
                outcome = self._outcome_cb(results)
            if outcome is None:
                outcome = self._default
        self._notify(self._termination_cbs, list(self._children), outcome)
        return outcome
