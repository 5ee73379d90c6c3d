"""Sequence: a StateMachine whose states run in the order added (smach's Sequence).

    seq = Sequence(outcomes=['succeeded', 'aborted', 'preempted'], connector_outcome='succeeded')
    seq.add('LEAVE', leave)            # 'succeeded' -> the next state; the last one -> 'succeeded'
    seq.add('SCORE', score)            # other outcomes go to the container outcome of that name
"""
from smart_brain.statemachine.container import classorinstancemethod
from smart_brain.statemachine.machine import StateMachine


class Sequence(StateMachine):
    def __init__(self, outcomes, connector_outcome, input_keys=(), output_keys=(), io_keys=()):
        StateMachine.__init__(self, outcomes, input_keys, output_keys, io_keys)
        self._connector = connector_outcome
        self._last = None

    def _add_seq(self, label, state, transitions=None, remapping=None, timeout=None):
        trans = {o: o for o in state.get_registered_outcomes() if o in self._outcomes}
        if timeout is not None and 'aborted' in self._outcomes:
            trans.setdefault('aborted', 'aborted')
        trans[self._connector] = self._connector
        trans.update(transitions or {})
        if self._last is not None and self._transitions[self._last].get(self._connector) == self._connector:
            self._transitions[self._last][self._connector] = label
        self._add_impl(label, state, trans, remapping, timeout)
        self._last = label
        return state

    add = classorinstancemethod(_add_seq)
