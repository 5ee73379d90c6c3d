"""A smach-style state machine library, without smach (not in Debian) and without its
known traps (see each module's docstring). Nothing here needs a ROS master except
ActionState's default client, MonitorState's default subscriber and the introspection
server.

    from smart_brain.statemachine import StateMachine, State, Concurrence, ActionState
"""
from smart_brain.statemachine.errors import (InvalidOutcomeError, InvalidStateError,  # noqa: F401
                                             InvalidTransitionError, InvalidUserCodeError, StateMachineError)
from smart_brain.statemachine.state import CBState, State, WaitState  # noqa: F401
from smart_brain.statemachine.userdata import Remapper, UserData  # noqa: F401
from smart_brain.statemachine.machine import StateMachine  # noqa: F401
from smart_brain.statemachine.concurrence import Concurrence  # noqa: F401
from smart_brain.statemachine.action_state import ActionState  # noqa: F401
from smart_brain.statemachine.monitor_state import MonitorState  # noqa: F401
from smart_brain.statemachine.trigger import Trigger  # noqa: F401
from smart_brain.statemachine.supervisor import Supervisor  # noqa: F401
from smart_brain.statemachine.runner import Runner  # noqa: F401
from smart_brain.statemachine.retry import Retry  # noqa: F401
from smart_brain.statemachine.sequence import Sequence  # noqa: F401
from smart_brain.statemachine.goal_guard import GOAL_GUARD, GoalGuard  # noqa: F401
from smart_brain.statemachine import goal_status  # noqa: F401
