"""The actionlib side of ActionState: one actionlib.ActionClient, polled without rospy time.

actionlib's wait_for_server() loops on rospy time, which never advances under sim time
without /clock; server_ready() makes the same checks once, so the caller can wait on a
monotonic clock. Goal handles expose the real GoalStatus (all ten values), not the
collapsed SimpleGoalState.
"""
import actionlib
from actionlib.action_client import CommState


class RosGoal(object):
    def __init__(self, handle):
        self._h = handle
        self._last_status = None  # after forget()

    def done(self):
        return self._h is None or self._h.get_comm_state() in (CommState.DONE, CommState.LOST)

    def status(self):
        if self._h is None:
            return self._last_status
        if self._h.get_comm_state() == CommState.LOST:
            return 9  # GoalStatus.LOST
        return self._h.get_goal_status()

    def result(self):
        return None if self._h is None else self._h.get_result()

    def cancel(self):
        if self._h is not None:
            self._h.cancel()

    def forget(self):
        # Python's actionlib has no stop_tracking_goal (C++ has): its client follows a goal as long
        # as the goal's handle lives. Keep the last status, drop the handle.
        self._last_status = self.status()
        self._h = None


class RosActionClient(object):
    def __init__(self, action_name, action_spec):
        self.action_name = action_name
        self._ac = actionlib.ActionClient(action_name, action_spec)

    def server_ready(self):
        ac = self._ac
        status = ac.last_status_msg
        if not status:
            return False
        server = status._connection_header['callerid']
        if not (ac.pub_goal.impl.has_connection(server) and ac.pub_cancel.impl.has_connection(server)):
            return False
        return (any(c.callerid_pub == server for c in ac.result_sub.impl.connections)
                and any(c.callerid_pub == server for c in ac.feedback_sub.impl.connections))

    def send(self, goal, on_change, on_feedback):
        handle = self._ac.send_goal(goal, transition_cb=lambda gh: on_change(),
                                    feedback_cb=lambda gh, fb: on_feedback(fb))
        return RosGoal(handle)
