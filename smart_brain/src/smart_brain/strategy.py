"""The Strategy contract (the original design's Strategy and StrategyLoader).

A strategy has a name, a one-line description and the HAL devices it needs. The brain
calls initialize() once, execute() in a loop at the brain's rate until it returns
False or the node stops, and finalize() once at the end, whatever happened.
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

    def initialize(self):
        """Set up subscriptions and publishers to HAL."""

    def execute(self):
        """One step of the strategy. Return False when finished."""
        return False

    def finalize(self):
        """Leave the robot safe: stop what this strategy started."""


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


def _load_builtin():
    # Importing the package registers every strategy module in it.
    import smart_brain.strategies  # noqa: F401
