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
"""


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


def create(name):
    """A new instance of the strategy called `name`; StrategyError naming the allowed values if unknown."""
    _load_builtin()
    if name not in _REGISTRY:
        raise StrategyError("parameter ~strategy = '%s': unknown strategy; allowed values: %s"
                            % (name, ', '.join(sorted(_REGISTRY))))
    return _REGISTRY[name]()


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
