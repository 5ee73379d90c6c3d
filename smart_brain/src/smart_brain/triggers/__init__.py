"""Triggers watched beside every machine strategy (statemachine/supervisor.py), one kind
per module, each made from its block under the brain's ~triggers parameter:

    triggers:
      opponent_ahead: {enabled: true, rangers: [front], distance: 0.3, ...}

A module defines KIND, read(cfg) -> its settings (every parameter read through `cfg`, a Config;
no ROS; `cfg.table` the TableSettings the brain read) and make(settings) -> statemachine.Trigger
with its ROS inputs and its handler state. build(blocks) makes every enabled one; settings(blocks)
reads them all without making any (the config check and the brain's parameter table).
"""
import importlib
import pkgutil

from robot_core.params import Params
from smart_brain.strategy import StrategyError
from smart_brain.table_settings import TableSettings

_KINDS = {}


def _load():
    if not _KINDS:
        for module in pkgutil.iter_modules(__path__):
            mod = importlib.import_module(__name__ + '.' + module.name)
            if hasattr(mod, 'KIND'):
                _KINDS[mod.KIND] = mod
    return _KINDS


def available():
    return sorted(_load())


def settings(triggers, only=None, table=None):
    """[(kind, enabled, settings)] of every block under `triggers` (the Params of ~triggers:
    {kind: {enabled: bool, ...}}; `only`: the kinds to read, None: all; `table`: the TableSettings,
    None: every table value at its default), each read and checked (unknown keys refused)."""
    kinds = _load()
    table = TableSettings.of(table)
    out = []
    for kind in sorted(triggers.keys()):
        if only is not None and kind not in only:
            triggers.unused(kind)
            continue
        if kind not in kinds:
            raise StrategyError("parameter ~triggers/%s: unknown trigger; allowed values: %s"
                                % (kind, ', '.join(sorted(kinds))))
        cfg = Config(kind, triggers, table)
        enabled = cfg.get('enabled', True, bool, meaning='false: the trigger is not watched (its settings are kept)')
        read = kinds[kind].read(cfg)
        cfg.done()
        out.append((kind, enabled, read))
    return out


def make(read):
    """Triggers for every enabled one of settings()' list."""
    return [_load()[kind].make(values) for kind, enabled, values in read if enabled]


def build(blocks, table=None):
    """Triggers for every enabled block of `blocks` ({kind: {enabled: bool, ...}})."""
    return make(settings(Params(blocks or {}, '~triggers'), table=table))


class Config(object):
    """Reads a trigger's block (~triggers/<kind>) through the brain's parameter reader, naming
    the parameter in every error; `table` is the TableSettings the brain read."""

    def __init__(self, kind, triggers, table):
        self.kind = kind
        self.params = triggers.block(kind)
        self.table = table

    def get(self, key, default, kind=float, allowed=None, meaning=''):
        return self.params.value(key, default, kind, allowed=allowed, meaning=meaning)

    def done(self):
        unknown = [line.split(' = ')[0].rsplit('/', 1)[1] for line in self.params.unasked()]
        if unknown:
            raise StrategyError('parameter ~triggers/%s: unknown key(s) %s' % (self.kind, ', '.join(sorted(unknown))))


def decision_param(cfg, key='then', meaning='what the handler decides when its wait runs out: resume, '
                   'restart, aborted or a state label'):
    """The handler's decision when its wait runs out: resume | restart | aborted | a state label."""
    return cfg.get(key, 'resume', str, meaning=meaning)
