"""RosGoal against the real actionlib: every method it calls on a goal handle exists on
Python's ClientGoalHandle (the brain once called stop_tracking_goal, which only C++ has, and the
strategy failed the first time a cancel was not confirmed), and a forgotten goal keeps its status."""
import ast
import inspect
import unittest

from actionlib.action_client import ClientGoalHandle, CommState

from smart_brain.statemachine import ros_action_client
from smart_brain.statemachine.ros_action_client import RosGoal


class Handle(object):
    """Answers like a ClientGoalHandle of an active goal."""

    def __init__(self):
        self.cancelled = False

    def get_comm_state(self):
        return CommState.ACTIVE

    def get_goal_status(self):
        return 1  # ACTIVE

    def get_result(self):
        return None

    def cancel(self):
        self.cancelled = True


class RosGoalTest(unittest.TestCase):
    def test_every_handle_method_it_calls_exists_in_python_actionlib(self):
        tree = ast.parse(inspect.getsource(ros_action_client.RosGoal))
        called = {n.func.attr for n in ast.walk(tree) if isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute)
                  and isinstance(n.func.value, ast.Attribute) and n.func.value.attr == '_h'}
        self.assertTrue(called)
        for name in called:
            self.assertTrue(hasattr(ClientGoalHandle, name), 'ClientGoalHandle has no %s' % name)

    def test_a_forgotten_goal_keeps_its_last_status_and_is_done(self):
        h = Handle()
        g = RosGoal(h)
        g.cancel()
        self.assertTrue(h.cancelled)
        g.forget()
        self.assertEqual(g.status(), 1)
        self.assertTrue(g.done())
        self.assertIsNone(g.result())
        g.cancel()  # nothing to cancel any more: no error


if __name__ == '__main__':
    unittest.main()
