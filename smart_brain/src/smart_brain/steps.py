"""Strategy steps from config: a list of {action: <registered action>, <its arguments>,
attempts: n} blocks (smart_brain/actions) built into a Sequence, each step retried while
it ends 'aborted'. Lets a robot's config describe a route without code."""
from smart_brain import actions
from smart_brain.statemachine import Retry, Sequence
from smart_brain.strategy import StrategyError


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
        try:
            state = actions.create(name, args)
        except ValueError as e:
            raise StrategyError('parameter %s[%d]: %s' % (where, i, e))
        seq.add(label, Retry(state, attempts) if attempts > 1 else state)
    return seq
