"""ActionState: all ten goal statuses, cancel on preempt, bounded waits, the match-end guard."""
import time
import unittest

import os  # noqa: E402
import sys  # noqa: E402

# catkin runs nose without adding this folder to the path; the shared helpers live here.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sm_helpers import ScriptedServer
from smart_brain.statemachine import ActionState, GoalGuard, Runner, goal_status

S = goal_status


def state(server, guard=None, **kw):
    return ActionState('/test/action', goal='goal', client=server, guard=guard or GoalGuard(), **kw)


class ActionStateTest(unittest.TestCase):
    def test_every_terminal_status_has_an_outcome(self):
        expected = {S.SUCCEEDED: 'succeeded', S.PREEMPTED: 'preempted', S.RECALLED: 'preempted',
                    S.ABORTED: 'aborted', S.REJECTED: 'aborted', S.LOST: 'aborted'}
        for status, outcome in expected.items():
            server = ScriptedServer(auto=status)
            self.assertEqual(state(server).run(None), outcome, S.name(status))
        self.assertEqual(len(S.NAMES), 10)
        for status in (S.PENDING, S.ACTIVE, S.PREEMPTING, S.RECALLING):
            self.assertIsNone(S.outcome_for(status))
        self.assertEqual(S.outcome_for(42), 'aborted')

    def test_preempted_by_someone_else_is_not_a_failure(self):
        self.assertEqual(state(ScriptedServer(auto=S.PREEMPTED, delay=0.05)).run(None), 'preempted')

    def test_custom_status_table_and_result_cb(self):
        st = state(ScriptedServer(auto=S.REJECTED), outcomes=['refused'], status_outcomes={S.REJECTED: 'refused'})
        self.assertEqual(st.run(None), 'refused')
        st = state(ScriptedServer(auto=S.SUCCEEDED), outcomes=['odd'], result_cb=lambda ud, status, r: 'odd')
        self.assertEqual(st.run(None), 'odd')

    def test_preempt_cancels_the_goal_and_returns_preempted(self):
        server = ScriptedServer()
        st = state(server)
        runner = Runner('a')
        runner.start(st)
        deadline = time.monotonic() + 2.0
        while not server.goals and time.monotonic() < deadline:
            time.sleep(0.005)
        t0 = time.monotonic()
        runner.preempt()
        self.assertTrue(runner.wait(1.0))
        self.assertLess(time.monotonic() - t0, 0.1)
        self.assertEqual(runner.outcome, 'preempted')
        self.assertEqual(server.goals[0].status(), S.PREEMPTED)

    def test_no_server_aborts_after_the_wait_timeout(self):
        st = state(ScriptedServer(ready=False), server_wait_timeout=0.2)
        t0 = time.monotonic()
        self.assertEqual(st.run(None), 'aborted')
        self.assertLess(time.monotonic() - t0, 0.5)

    def test_exec_timeout_cancels_and_aborts(self):
        server = ScriptedServer()
        self.assertEqual(state(server, exec_timeout=0.1).run(None), 'aborted')
        self.assertGreaterEqual(server.goals[0].cancels, 1)
        self.assertEqual(server.goals[0].status(), S.PREEMPTED)

    def test_unconfirmed_cancel_does_not_hang(self):
        server = ScriptedServer(confirm_cancel=False)
        st = state(server, preempt_timeout=0.2)
        runner = Runner('a')
        runner.start(st)
        while not server.goals:
            time.sleep(0.005)
        runner.preempt()
        self.assertTrue(runner.wait(1.0))
        self.assertEqual(runner.outcome, 'preempted')
        self.assertGreaterEqual(server.goals[0].cancels, 2)
        self.assertTrue(server.goals[0].forgotten)

    def test_guard_cancels_running_goals_and_refuses_new_ones(self):
        guard = GoalGuard()
        server = ScriptedServer()
        runner = Runner('a')
        runner.start(state(server, guard))
        while not server.goals:
            time.sleep(0.005)
        self.assertEqual(guard.close('match over'), 1)
        self.assertTrue(runner.wait(1.0))
        self.assertEqual(runner.outcome, 'aborted')
        self.assertEqual(server.goals[0].status(), S.PREEMPTED)
        self.assertEqual(state(server, guard).run(None), 'aborted')
        self.assertEqual(len(server.goals), 1, 'a goal was sent after the guard closed')
        self.assertEqual(guard.active(), 0)

    def test_goal_from_userdata_and_result_into_userdata(self):
        from smart_brain.statemachine import UserData, Remapper
        server = ScriptedServer(auto=S.SUCCEEDED)
        st = ActionState('/a', goal_key='target', result_key='report', client=server, guard=GoalGuard())
        ud = UserData(target='there')
        self.assertEqual(st.run(Remapper(ud, st.get_registered_input_keys(), st.get_registered_output_keys())), 'succeeded')
        self.assertEqual(server.goals[0].goal, 'there')
        self.assertEqual(ud.report, 'result')


if __name__ == '__main__':
    unittest.main()
