"""The match-end guard above every strategy: tracks every goal an action state sends, and
close() cancels them all and refuses any new one until reopen(). The brain closes it at
the end of the match, so no strategy has to remember to."""
import logging
import threading

log = logging.getLogger('smart_brain.statemachine')


class GoalGuard(object):
    def __init__(self):
        self._lock = threading.Lock()
        self._goals = {}     # id -> cancel function
        self._closed = False
        self._reason = ''
        self._next = 0

    def admit(self, cancel):
        """Register a goal about to be sent; returns its id, or None if goals are refused."""
        with self._lock:
            if self._closed:
                return None
            self._next += 1
            self._goals[self._next] = cancel
            return self._next

    def release(self, goal_id):
        with self._lock:
            self._goals.pop(goal_id, None)

    def close(self, reason='closed'):
        """Refuse new goals and cancel every tracked one; returns how many were cancelled."""
        with self._lock:
            self._closed = True
            self._reason = reason
            cancels = list(self._goals.values())
        for cancel in cancels:
            try:
                cancel()
            except Exception as e:
                log.error('goal guard: cancelling a goal failed: %s', e)
        return len(cancels)

    def reopen(self):
        with self._lock:
            self._closed = False

    @property
    def closed(self):
        return self._closed

    @property
    def reason(self):
        return self._reason

    def active(self):
        with self._lock:
            return len(self._goals)


#: the process-wide guard every ActionState uses unless given another
GOAL_GUARD = GoalGuard()
