"""Errors of the state machine library (smach users know them as InvalidStateError etc.)."""


class StateMachineError(Exception):
    """Base of every error raised by the library."""


class InvalidStateError(StateMachineError):
    """A state was added or referenced wrongly (duplicate label, unknown state)."""


class InvalidTransitionError(StateMachineError):
    """A transition targets nothing, or an outcome has no transition."""


class InvalidOutcomeError(StateMachineError):
    """A state returned an outcome it did not declare."""


class InvalidUserCodeError(StateMachineError):
    """User code (a state's execute, a callback) raised; the original is chained."""
