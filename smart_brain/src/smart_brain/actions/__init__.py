"""Actions: reusable states over the HAL interface, one per module, each registered by
name so the BrainSlave (the StartAction service) can start it from a name and arguments.

    @register_action('goto')
    def goto(x, y, angle=0.0, ...): return <a State>
"""
import importlib
import pkgutil

_ACTIONS = {}


def register_action(name):
    def deco(factory):
        if name in _ACTIONS and _ACTIONS[name] is not factory:
            raise ValueError('two actions named %r' % name)
        _ACTIONS[name] = factory
        return factory
    return deco


def available():
    return sorted(_ACTIONS)


def create(name, args=None):
    """A new state for action `name` built with keyword `args`; ValueError naming the allowed values."""
    if name not in _ACTIONS:
        raise ValueError("unknown action '%s'; allowed values: %s" % (name, ', '.join(available())))
    try:
        return _ACTIONS[name](**(args or {}))
    except TypeError as e:
        raise ValueError('action %s: bad arguments %r: %s' % (name, args, e))


for _module in pkgutil.iter_modules(__path__):
    importlib.import_module(__name__ + '.' + _module.name)
