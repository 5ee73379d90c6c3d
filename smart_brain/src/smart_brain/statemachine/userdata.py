"""Userdata: the key/value store states share, and the remapped view each child gets.

As in smach: a container owns a UserData; a child sees it through a Remapper that only
lets it read its input keys and write its output keys, under the names it knows
(`remapping` maps the child's key to the container's key).
"""
import threading

from smart_brain.statemachine.errors import StateMachineError


class UserData(object):
    def __init__(self, **initial):
        object.__setattr__(self, '_data', dict(initial))
        object.__setattr__(self, '_lock', threading.RLock())

    def keys(self):
        with self._lock:
            return list(self._data.keys())

    def __contains__(self, key):
        with self._lock:
            return key in self._data

    def __getitem__(self, key):
        with self._lock:
            if key not in self._data:
                raise KeyError("userdata has no key '%s' (keys: %s)" % (key, ', '.join(sorted(self._data)) or 'none'))
            return self._data[key]

    def __setitem__(self, key, value):
        with self._lock:
            self._data[key] = value

    def __getattr__(self, key):
        if key.startswith('_'):
            raise AttributeError(key)
        try:
            return self[key]
        except KeyError as e:
            raise AttributeError(str(e))

    def __setattr__(self, key, value):
        if key.startswith('_'):
            raise AttributeError('userdata keys may not start with _: %s' % key)
        self[key] = value

    def get(self, key, default=None):
        with self._lock:
            return self._data.get(key, default)

    def update(self, other):
        with self._lock:
            for key in other.keys():
                self._data[key] = other[key]

    def snapshot(self):
        with self._lock:
            return dict(self._data)


class Remapper(object):
    """A child's window onto its container's userdata."""

    def __init__(self, ud, input_keys, output_keys, remapping=None):
        object.__setattr__(self, '_ud', ud)
        object.__setattr__(self, '_inputs', frozenset(input_keys))
        object.__setattr__(self, '_outputs', frozenset(output_keys))
        object.__setattr__(self, '_remap', dict(remapping or {}))

    def _outer(self, key):
        return self._remap.get(key, key)

    def keys(self):
        return [k for k in self._inputs if self._outer(k) in self._ud]

    def __contains__(self, key):
        return key in self._inputs and self._outer(key) in self._ud

    def __getitem__(self, key):
        if key not in self._inputs:
            raise StateMachineError("reading userdata key '%s' which is not an input key (input keys: %s)"
                                    % (key, ', '.join(sorted(self._inputs)) or 'none'))
        return self._ud[self._outer(key)]

    def __setitem__(self, key, value):
        if key not in self._outputs:
            raise StateMachineError("writing userdata key '%s' which is not an output key (output keys: %s)"
                                    % (key, ', '.join(sorted(self._outputs)) or 'none'))
        self._ud[self._outer(key)] = value

    def __getattr__(self, key):
        if key.startswith('_'):
            raise AttributeError(key)
        return self[key]

    def __setattr__(self, key, value):
        self[key] = value

    def get(self, key, default=None):
        return self[key] if key in self else default
