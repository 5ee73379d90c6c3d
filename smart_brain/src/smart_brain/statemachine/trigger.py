"""Trigger: a condition watched beside the running state, with debounce.

condition() is polled by its Supervisor (and re-polled at once when the trigger calls
self.notify(), e.g. from a subscriber callback). It fires when the condition has held
for `debounce` seconds and at least `holdoff` seconds have passed since its handler last
ended, so a flapping sensor neither fires on a single sample nor loops the handler.
`handler` is a State whose outcome tells the supervisor what to do next (supervisor.py).
"""
from smart_brain.statemachine import clock


class Trigger(object):
    def __init__(self, name, condition, handler, debounce=0.0, holdoff=1.0, priority=0, on_fire=None):
        self.name = name
        #: called by the supervisor the moment the trigger fires, before preempting the body
        #: (e.g. zero wheel speed at once rather than after the body has stopped)
        self.on_fire = on_fire
        self.condition = condition
        self.handler = handler
        self.debounce = float(debounce)
        self.holdoff = float(holdoff)
        self.priority = priority
        self.fired = 0
        self._true_since = None
        self._handled_at = None
        self._notify = None

    def attach(self, notify):
        """Called by the supervisor: notify() makes it poll now."""
        self._notify = notify

    def notify(self):
        if self._notify is not None:
            self._notify()

    def reset(self):
        self._true_since = None

    def update(self, now=None):
        """Poll once; True when the trigger fires now."""
        now = clock.now() if now is None else now
        if not self.condition():
            self._true_since = None
            return False
        if self._true_since is None:
            self._true_since = now
        if now - self._true_since < self.debounce:
            return False
        if self._handled_at is not None and now - self._handled_at < self.holdoff:
            return False
        self.fired += 1
        self._true_since = None
        self._handled_at = now
        return True

    def handled(self, now=None):
        """The handler ended: the holdoff counts from here."""
        self._handled_at = clock.now() if now is None else now
