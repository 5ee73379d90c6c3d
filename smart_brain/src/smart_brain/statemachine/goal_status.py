"""All ten actionlib GoalStatus values and what they mean to a state.

A goal preempted or recalled by someone else is 'preempted', not a failure (smach_ros
reported it as aborted); LOST (the server forgot the goal) and REJECTED are 'aborted'.
The four non-terminal values mean "keep waiting"; a wait that runs out while in them is
escalated to a cancel and 'aborted' by the action state.
"""
PENDING = 0      # not yet processed by the server
ACTIVE = 1       # being processed
PREEMPTED = 2    # cancelled after it started: terminal
SUCCEEDED = 3    # terminal
ABORTED = 4      # the server gave up: terminal
REJECTED = 5     # refused without processing: terminal
PREEMPTING = 6   # cancel requested while active, not yet confirmed
RECALLING = 7    # cancel requested while pending, not yet confirmed
RECALLED = 8     # cancelled before it started: terminal
LOST = 9         # the client lost track of it (server gone): terminal

NAMES = {PENDING: 'PENDING', ACTIVE: 'ACTIVE', PREEMPTED: 'PREEMPTED', SUCCEEDED: 'SUCCEEDED',
         ABORTED: 'ABORTED', REJECTED: 'REJECTED', PREEMPTING: 'PREEMPTING', RECALLING: 'RECALLING',
         RECALLED: 'RECALLED', LOST: 'LOST'}

TERMINAL = frozenset((PREEMPTED, SUCCEEDED, ABORTED, REJECTED, RECALLED, LOST))
WAITING = frozenset((PENDING, ACTIVE, PREEMPTING, RECALLING))

DEFAULT_OUTCOMES = {
    SUCCEEDED: 'succeeded',
    PREEMPTED: 'preempted',
    RECALLED: 'preempted',
    ABORTED: 'aborted',
    REJECTED: 'aborted',
    LOST: 'aborted',
}


def name(status):
    return NAMES.get(status, 'UNKNOWN(%r)' % (status,))


def outcome_for(status, table=None):
    """The outcome for a terminal status; None while the goal is still going."""
    if status in WAITING:
        return None
    if status not in TERMINAL:
        return 'aborted'    # a value outside the ten: never wait on it
    return (table or DEFAULT_OUTCOMES).get(status, DEFAULT_OUTCOMES[status])
