"""The brain's parameters (block `brain:` of config/<robot>.yaml, the brain node's ~), read by one
reader (robot_core.params) with no ROS: by the brain at start, and by `check_config` and the
parameter table (`make docs`, scripts/check_brain_config) from a config file, so a wrong value
or a key no reader knows is said before anything starts.

BrainSettings reads the node's own values and creates the strategy to run (its read_config reads
its block and the triggers'); read_config() also reads the block of every other strategy present
(one the operator may switch to), after which unknown() lists what no reader asked for. Every
strategy gets the same TableSettings (table_settings.py), the /table values read once.
"""
from robot_core.params import REQUIRED, Params
from smart_brain import strategy as strategies
from smart_brain import triggers as trigger_kinds
from smart_brain.strategy import StrategyError
from smart_brain.table_settings import TableSettings

#: the brain's own blocks (a strategy's block has its name; the strategy `match` has none)
BRAIN_BLOCKS = ('match', 'ready')


class BrainSettings(object):
    def __init__(self, params, table, strategy=None):
        """`params`: the brain's Params; `table`: the TableSettings; `strategy`: the strategy
        to run (None: ~strategy)."""
        strategies.load_modules(params.value(
            'strategy_modules', [], list, meaning='extra Python modules that @register strategies',
            check=lambda v: '' if all(isinstance(m, str) for m in v) else 'must be a list of Python module names'))
        if strategy:
            params.unused('strategy')  # the caller's choice replaces the config's
            name = strategy
        elif not params.has('strategy'):
            raise StrategyError('missing required parameter %s; allowed values: %s'
                                % (params.qualified('strategy'), ', '.join(strategies.available())))
        else:
            name = params.value('strategy', REQUIRED, str, meaning='the strategy the brain runs (a registered '
                                'name; check_config --strategy and make run STRATEGY= replace it)')
        self.rate_hz = params.positive('rate', 10.0, '[Hz] how often the strategy\'s execute() runs')
        self.device_timeout = params.positive('device_timeout', 10.0,
                                              "[s] how long to wait for the strategy's HAL devices and topics")
        self.strategy = strategies.create(str(name), params, table)
        match = params.block(BRAIN_BLOCKS[0])
        self.timed = match.value('enabled', self.strategy.timed, bool, default_named="the strategy's `timed`",
                                 meaning='run under the match timer: wait for the start signal, stop at the match end')
        self.duration = match.positive('duration', 90.0, '[s] start signal to match end (simulated seconds in '
                                       'simulation, the monotonic clock on the robot)')
        self.start_mode = match.value('start', 'cord', str, allowed=('cord', 'immediate'),
                                      meaning='cord: wait for the start signal; immediate: start at once')
        self.start_topic = match.value('start_topic', '/hal/hmi/input', str,
                                       meaning='the HAL human interface (hal_nodes/HumanInput, `started`)')
        self.funny = match.value('funny_action', False, bool,
                                 meaning="run the strategy's funny_action() after the match end")
        self.deactivate_service = match.value('deactivate_service', '/effectors/deactivate', str,
                                              meaning='std_srvs/Trigger that switches the effectors off at the end')
        self.end_topic = match.value('end_topic', '/effectors/match_end', str,
                                     meaning="std_msgs/Time, latched: the match's end, by which hal_node "
                                     'switches the effectors off itself')
        self.saved_match = match.value('resume', None, dict, meaning='written by the brain at the start '
                                       '({started_at, clock, strategy}): a brain respawned mid-match resumes it')
        if not self.timed:
            self.saved_match = None
        ready = params.block(BRAIN_BLOCKS[1])
        self.ready_nodes = ready.value('nodes', ['/hcl', '/hal'], list, meaning='the nodes whose status "ready" needs '
                                       '(smart_brain/readiness.py)')
        self.ready_optional = ready.value('optional', [], list, meaning='nodes reported but not needed')
        self.ready_grace = ready.positive('grace', 15.0, '[s, wall] at start-up "not ready" is logged at INFO this '
                                          'long, then WARN')
        self.ready_display = ready.value('display', '/hal/hmi/text', str,
                                         meaning='the HMI display\'s text input (std_msgs/String)')


def read_config(brain, table, strategy=None):
    """(Params, BrainSettings) of a `brain:` block with every strategy block in it read too; `table`:
    the TableSettings or the /table dictionary. Raises ParameterError or StrategyError at the
    first wrong value."""
    params = brain if isinstance(brain, Params) else Params(brain or {}, '/brain')
    table = TableSettings.of(table)
    settings = BrainSettings(params, table, strategy)
    running = {settings.strategy.name, getattr(getattr(settings.strategy, '_impl', None), 'name', None)}
    for name in strategies.available():
        if name not in running and strategies.strategy_class(name).configured_in(params):
            strategies.create(name, params, table)
    return params, settings


def read_unconfigured(params, table):
    """A reader of its own over the brain's namespace through which every registered strategy and
    trigger kind that `params` (after read_config) holds no declaration of has read an empty
    block: what each declares at its defaults, for the parameter table (check_brain_config
    --describe) of what no config sets up. `table`: the TableSettings or the /table dictionary."""
    table = TableSettings.of(table)
    declared = [name.split('/') for name in params.declarations()]
    kinds_read = {parts[1] for parts in declared if parts[0] == 'triggers' and len(parts) > 2}
    kinds = [k for k in trigger_kinds.available() if k not in kinds_read]
    names = [n for n in strategies.available() if n not in BRAIN_BLOCKS and n not in {parts[0] for parts in declared}]
    tree = dict({n: {} for n in names}, triggers={k: {} for k in kinds})
    empty = Params(tree, params.ns)
    empty._record.describing = True  # a required value reads as None and the reader declares on (describe_node)
    trigger_kinds.settings(empty.block('triggers'), table=table)
    for name in names:
        strategies.create(name, empty, table)
    return empty


def unknown(params):
    """A line per value of the brain's block no reader asks for (a typo, or a setting of nothing);
    the block of a strategy not read (not the one running), or the triggers' under a strategy
    that runs none, is not one."""
    known = set(strategies.available()) | {'triggers'}
    return ['parameter %s: no reader knows it' % line for line in params.unasked()
            if line.split(' = ')[0][len(params.ns) + 1:] not in known]
