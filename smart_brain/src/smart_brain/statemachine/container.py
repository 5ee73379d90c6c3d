"""What every container (StateMachine, Concurrence, Supervisor) shares: children, its own
userdata, callbacks for introspection, and the `with container:` construction idiom."""
import threading

from smart_brain.statemachine.errors import InvalidStateError
from smart_brain.statemachine.state import State
from smart_brain.statemachine.userdata import UserData

_open = threading.local()


def opened_container(kind):
    """The innermost container opened with `with` in this thread (smach's add-without-self)."""
    stack = getattr(_open, 'stack', [])
    if not stack:
        raise InvalidStateError('%s.add() called outside a `with <container>:` block' % kind.__name__)
    container = stack[-1]
    if not isinstance(container, kind):
        raise InvalidStateError('%s.add() inside a `with` block of a %s' % (kind.__name__, type(container).__name__))
    return container


class classorinstancemethod(object):
    """`Container.add(...)` inside `with` (smach style) and `container.add(...)` both work."""

    def __init__(self, fn):
        self._fn = fn

    def __get__(self, obj, cls):
        def bound(*args, **kwargs):
            target = obj if obj is not None else opened_container(cls)
            return self._fn(target, *args, **kwargs)
        bound.__doc__ = self._fn.__doc__
        return bound


class Container(State):
    def __init__(self, outcomes=(), input_keys=(), output_keys=(), io_keys=()):
        State.__init__(self, outcomes, input_keys, output_keys, io_keys)
        self.userdata = UserData()
        self._children = {}          # label -> State, in insertion order
        self._lock = threading.RLock()
        self._start_cbs = []
        self._transition_cbs = []
        self._termination_cbs = []

    def __enter__(self):
        _open.stack = getattr(_open, 'stack', []) + [self]
        return self

    def __exit__(self, *exc):
        _open.stack = _open.stack[:-1]
        if exc[0] is None:
            self.check_consistency()
        return False

    def _add_child(self, label, state):
        if not isinstance(state, State):
            raise InvalidStateError('child %r is a %s, not a State' % (label, type(state).__name__))
        if label in self._children:
            raise InvalidStateError("a state labelled '%s' is already in this container" % label)
        if label in self._outcomes:
            raise InvalidStateError("label '%s' is also an outcome of the container" % label)
        self._children[label] = state

    def __getitem__(self, label):
        return self._children[label]

    def get_children(self):
        return dict(self._children)

    def check_consistency(self):
        """Raise if the container cannot run as built."""

    # ---- introspection interface (smach names) ----
    def get_active_states(self):
        raise NotImplementedError

    def get_initial_states(self):
        raise NotImplementedError

    def get_internal_edges(self):
        """[(outcome, from_label, to_label_or_container_outcome)]"""
        raise NotImplementedError

    def register_start_cb(self, cb):
        self._start_cbs.append(cb)

    def register_transition_cb(self, cb):
        self._transition_cbs.append(cb)

    def register_termination_cb(self, cb):
        self._termination_cbs.append(cb)

    def _notify(self, cbs, *args):
        for cb in list(cbs):
            cb(self, *args)

    def _parent_view(self, parent_ud):
        """Copy the container's input keys in from the parent's userdata."""
        if parent_ud is None:
            return
        for key in self._input_keys:
            if key in parent_ud:
                self.userdata[key] = parent_ud[key]

    def _write_back(self, parent_ud):
        if parent_ud is None:
            return
        for key in self._output_keys:
            if key in self.userdata:
                parent_ud[key] = self.userdata[key]

    def execute(self, parent_ud=None):
        """Run the container; callable directly (smach's sm.execute()) or through run()."""
        began = self._begin()
        try:
            self._parent_view(parent_ud)
            outcome = self._execute_container()
            self._write_back(parent_ud)
            return outcome
        finally:
            if began:
                self._end()

    def _execute_container(self):
        raise NotImplementedError

    # ---- history (see supervisor.py) ----
    def resume_next(self):
        """The next execute() continues where the last one was preempted (deep history)."""

    def restart_next(self, label=None):
        """The next execute() starts at `label` (or the initial state)."""
