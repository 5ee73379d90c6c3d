"""Triggers watched beside every machine strategy (statemachine/supervisor.py), one kind
per module, each made from its block under the brain's ~triggers parameter:

    triggers:
      opponent_ahead: {enabled: true, rangers: [front], distance: 0.3, ...}

A module defines KIND and make(config) -> statemachine.Trigger with its ROS inputs and
its handler state. build(params) makes every enabled one.
"""
import importlib
import pkgutil

from smart_brain.strategy import StrategyError

_KINDS = {}


def _load():
    if not _KINDS:
        for module in pkgutil.iter_modules(__path__):
            mod = importlib.import_module(__name__ + '.' + module.name)
            if hasattr(mod, 'KIND'):
                _KINDS[mod.KIND] = mod.make
    return _KINDS


def available():
    return sorted(_load())


def build(params):
    """Triggers for every enabled block of `params` ({kind: {enabled: bool, ...}})."""
    kinds = _load()
    out = []
    for kind, config in sorted((params or {}).items()):
        if kind not in kinds:
            raise StrategyError("parameter ~triggers/%s: unknown trigger; allowed values: %s"
                                % (kind, ', '.join(sorted(kinds))))
        config = dict(config or {})
        if config.pop('enabled', True):
            out.append(kinds[kind](config))
    return out


class Config(object):
    """Reads a trigger's block, naming the parameter in every error."""

    def __init__(self, kind, values):
        self.kind = kind
        self._values = dict(values)

    def get(self, key, default, kind=float, allowed=None):
        value = self._values.pop(key, default)
        try:
            value = kind(value) if kind not in (list,) else list(value)
        except (TypeError, ValueError):
            raise StrategyError('parameter ~triggers/%s/%s = %r: must be a %s' % (self.kind, key, value, kind.__name__))
        if allowed is not None and value not in allowed:
            raise StrategyError('parameter ~triggers/%s/%s = %r: allowed values: %s'
                                % (self.kind, key, value, ', '.join(map(str, allowed))))
        return value

    def done(self):
        if self._values:
            raise StrategyError('parameter ~triggers/%s: unknown key(s) %s' % (self.kind, ', '.join(sorted(self._values))))


def decision_param(cfg, key='then'):
    """The handler's decision when its wait runs out: resume | restart | aborted | a state label."""
    return cfg.get(key, 'resume', str)
