"""Strategy steps from config: a list of {action: <registered action>, <its arguments>,
attempts: n, on_abort: stop|continue} blocks (smart_brain/actions) built into a Sequence,
each step retried while it ends 'aborted'. on_abort: continue makes a step best-effort: when
every attempt aborted the sequence goes on (e.g. the driver stopped short of the unloading
pose for a wall echo: unloading from there still scores). Lets a robot's config describe a
route without code."""
import logging
from smart_brain import actions
from smart_brain.statemachine import Retry, Sequence
from smart_brain.strategy import StrategyError

log = logging.getLogger('smart_brain.statemachine')


class BestEffort(Retry):
    """Retry whose final 'aborted' becomes 'succeeded': the sequence goes on from where it is."""

    def __init__(self, state, attempts, label):
        Retry.__init__(self, state, attempts)
        self.label = label

    def execute(self, ud):
        outcome = Retry.execute(self, ud)
        if outcome == 'aborted':
            log.warning('step %s aborted %d time(s): going on from here (on_abort: continue)', self.label, self.tries)
            return 'succeeded'
        return outcome


def build_sequence(steps, where, outcomes=('succeeded', 'aborted', 'preempted'), default_attempts=2):
    seq = Sequence(outcomes=list(outcomes), connector_outcome='succeeded')
    if not steps:
        raise StrategyError('parameter %s: empty; give a list of {action: <name>, ...} steps' % where)
    for i, step in enumerate(steps):
        if not isinstance(step, dict) or 'action' not in step:
            raise StrategyError('parameter %s[%d] = %r: must be a mapping with an `action` (allowed: %s)'
                                % (where, i, step, ', '.join(actions.available())))
        args = dict(step)
        name = args.pop('action')
        attempts = int(args.pop('attempts', default_attempts))
        label = args.pop('label', '%02d_%s' % (i + 1, name.upper()))
        on_abort = args.pop('on_abort', 'stop')
        if on_abort not in ('stop', 'continue'):
            raise StrategyError("parameter %s[%d]/on_abort = %r: allowed values: stop, continue" % (where, i, on_abort))
        try:
            state = actions.create(name, args)
        except ValueError as e:
            raise StrategyError('parameter %s[%d]: %s' % (where, i, e))
        if on_abort == 'continue':
            state = BestEffort(state, attempts, label)
        elif attempts > 1:
            state = Retry(state, attempts)
        seq.add(label, state)
    return seq
