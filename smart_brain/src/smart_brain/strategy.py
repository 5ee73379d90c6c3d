"""The Strategy contract (a Strategy and its StrategyLoader).

A strategy has a name, a one-line description and the HAL devices it needs. The brain
calls initialize() once, execute() in a loop at the brain's rate until it returns
False or the node stops, and finalize() once at the end, whatever happened.

Added for the match (all optional, with defaults that keep older strategies working):
`timed` puts the strategy under the match timer (start signal, match end); `stop()` is
called from another thread at the match end or on a strategy switch and must make
execute() wind down promptly; `funny_action()` runs after the match end when configured;
`required_topics` lists topics outside /hal the strategy needs (e.g. /mcl/pose).
A strategy built as a state machine derives from machine_strategy.MachineStrategy.

Its parameters (its block ~<name> of the brain node) are read in read_config(), before anything
else and with no ROS, so a wrong value stops the brain at once and `check_config` and the
parameter table (`make docs`) read a config file the same way; `parameters` says what each key
means (a key read without a meaning there fails test_parameter_tables).
"""
from smart_brain.table_settings import TableSettings


class StrategyError(Exception):
    """A strategy cannot run (a device is missing, a parameter is wrong)."""


class Strategy(object):
    #: registry name, used by the ~strategy parameter
    name = None
    #: one line for logs and the strategy list
    description = ''
    #: HAL device names (under /hal) this strategy needs, checked before initialize()
    required_devices = ()
    #: other topics this strategy needs (absolute names), checked like the devices
    required_topics = ()
    #: under the match timer: waits for the start signal, stopped at the match end
    timed = True
    #: what each key of the strategy's block means, in a line ('tracker/gate' for a key of a
    #: dictionary the strategy reads key by key): the meaning column of the brain's parameter table
    parameters = {}
    @classmethod
    def configured_in(cls, brain):
        """Whether a config sets this strategy up (its block is in `brain`, the brain's Params):
        check_config then reads it too, not only the one the brain runs."""
        return brain.has(cls.name)

    def read_config(self, brain, table):
        """Read this strategy's parameters with no ROS: `brain` is the brain node's reader (a
        robot_core.params.Params; the strategy's own block is brain.block(self.name)), `table`
        the robot's table description (a table_settings.TableSettings, read once by the brain).
        Called once, before initialize(); a bad value raises ParameterError or StrategyError
        naming it."""
        self.params = brain.block(self.name)
        for key, meaning in self.parameters.items():
            self.params.describe(key, meaning)

    def ensure_config(self):
        """read_config() from the parameter server, for a strategy created without the brain's reader."""
        if getattr(self, 'params', None) is None:
            from robot_core.params import Params
            self.read_config(Params.from_server('~'), TableSettings.from_server())

    def initialize(self):
        """Set up subscriptions and publishers to HAL."""

    def execute(self):
        """One step of the strategy. Return False when finished."""
        return False

    def finalize(self):
        """Leave the robot safe: stop what this strategy started."""

    def stop(self):
        """Called from another thread (match end, strategy switch): make execute() return False soon."""

    def funny_action(self):
        """The end-of-match hook, run after every effector was deactivated, only if configured."""


_REGISTRY = {}


def register(cls):
    """Class decorator adding a Strategy subclass to the registry under cls.name."""
    if not cls.name:
        raise ValueError('strategy %s has no name' % cls.__name__)
    if cls.name in _REGISTRY and _REGISTRY[cls.name] is not cls:
        raise ValueError('two strategies named %r: %s and %s' % (cls.name, _REGISTRY[cls.name].__name__, cls.__name__))
    _REGISTRY[cls.name] = cls
    return cls


def available():
    """Sorted names of the registered strategies."""
    _load_builtin()
    return sorted(_REGISTRY)


def create(name, brain=None, table=None):
    """A new instance of the strategy called `name`; StrategyError naming the allowed values if unknown.
    With `brain` (the brain node's Params) and `table` (the TableSettings, or the /table
    dictionary), its parameters are read (read_config)."""
    _load_builtin()
    if name not in _REGISTRY:
        raise StrategyError("parameter ~strategy = '%s': unknown strategy; allowed values: %s"
                            % (name, ', '.join(sorted(_REGISTRY))))
    strategy = _REGISTRY[name]()
    if brain is not None:
        strategy.read_config(brain, TableSettings.of(table))
    return strategy


def strategy_class(name):
    """The registered class of strategy `name` (None when unknown)."""
    _load_builtin()
    return _REGISTRY.get(name)


def load_modules(names):
    """Import extra modules that @register strategies (the brain's ~strategy_modules)."""
    import importlib
    for name in names:
        try:
            importlib.import_module(name)
        except ImportError as e:
            raise StrategyError('parameter ~strategy_modules: cannot import %s: %s' % (name, e))


def _load_builtin():
    # Importing the package registers every strategy module in it.
    import smart_brain.strategies  # noqa: F401
