"""StateMachine: transitions, nesting, userdata remapping, consistency checks, timeouts."""
import time
import unittest

import os  # noqa: E402
import sys  # noqa: E402

# catkin runs nose without adding this folder to the path; the shared helpers live here.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sm_helpers import Counter, Sleeper
from smart_brain.statemachine import (CBState, InvalidOutcomeError, InvalidTransitionError, StateMachine,
                                      StateMachineError, State)


class AddOne(State):
    def __init__(self):
        State.__init__(self, outcomes=['ok'], input_keys=['value'], output_keys=['value'])

    def execute(self, ud):
        ud.value = ud.value + 1
        return 'ok'


class MachineTest(unittest.TestCase):
    def test_transitions_follow_outcomes(self):
        a, b, c = Counter('next'), Counter('fail'), Counter('next')
        sm = StateMachine(outcomes=['good', 'bad'])
        with sm:
            StateMachine.add('A', a, transitions={'next': 'B', 'preempted': 'bad'})
            StateMachine.add('B', b, transitions={'fail': 'bad', 'preempted': 'bad'})
            StateMachine.add('C', c, transitions={'next': 'good', 'preempted': 'bad'})
        self.assertEqual(sm.execute(), 'bad')
        self.assertEqual((a.runs, b.runs, c.runs), (1, 1, 0))
        sm.set_initial_state(['C'])
        self.assertEqual(sm.execute(), 'good')
        self.assertEqual(c.runs, 1)

    def test_nested_machine_outcome_is_a_transition_of_the_parent(self):
        inner = StateMachine(outcomes=['x', 'y'])
        inner.add('I', Counter('go'), transitions={'go': 'y', 'preempted': 'x'})
        outer = StateMachine(outcomes=['end_x', 'end_y'])
        outer.add('SUB', inner, transitions={'x': 'end_x', 'y': 'end_y'})
        self.assertEqual(outer.execute(), 'end_y')

    def test_userdata_remapping_reads_and_writes_under_container_names(self):
        sm = StateMachine(outcomes=['done'])
        sm.userdata.counter = 40
        with sm:
            StateMachine.add('ONE', AddOne(), transitions={'ok': 'TWO'}, remapping={'value': 'counter'})
            StateMachine.add('TWO', AddOne(), transitions={'ok': 'done'}, remapping={'value': 'counter'})
        sm.execute()
        self.assertEqual(sm.userdata.counter, 42)
        self.assertNotIn('value', sm.userdata)

    def test_nested_input_and_output_keys_cross_containers(self):
        inner = StateMachine(outcomes=['done'], input_keys=['value'], output_keys=['value'])
        inner.add('ADD', AddOne(), transitions={'ok': 'done'})
        outer = StateMachine(outcomes=['done'])
        outer.userdata.n = 1
        outer.add('SUB', inner, transitions={'done': 'done'}, remapping={'value': 'n'})
        outer.execute()
        self.assertEqual(outer.userdata.n, 2)

    def test_undeclared_keys_are_refused(self):
        def write_other(ud):
            ud.other = 1
            return 'ok'

        def read_other(ud):
            return 'ok' if ud.other else 'ok'
        for cb in (write_other, read_other):
            sm = StateMachine(outcomes=['done'])
            sm.userdata.other = 1
            sm.add('S', CBState(cb, outcomes=['ok']), transitions={'ok': 'done'})
            with self.assertRaises(StateMachineError) as ctx:
                sm.execute()
            self.assertIn("'other'", str(ctx.exception))

    def test_missing_transition_is_reported_with_the_state_and_outcome(self):
        sm = StateMachine(outcomes=['done'])
        with self.assertRaises(InvalidTransitionError) as ctx:
            with sm:
                StateMachine.add('A', Counter('go', extra=['oops']), transitions={'go': 'done', 'preempted': 'done'})
        self.assertIn('A', str(ctx.exception))
        self.assertIn("'oops'", str(ctx.exception))

    def test_transition_to_nowhere_is_refused(self):
        sm = StateMachine(outcomes=['done'])
        sm.add('A', Counter('go'), transitions={'go': 'NOWHERE', 'preempted': 'done'})
        with self.assertRaises(InvalidTransitionError):
            sm.check_consistency()

    def test_undeclared_outcome_is_an_error(self):
        sm = StateMachine(outcomes=['done'])
        sm.add('A', CBState(lambda ud: 'surprise', outcomes=['ok']), transitions={'ok': 'done'})
        with self.assertRaises(InvalidOutcomeError):
            sm.execute()

    def test_timeout_preempts_the_state_and_aborts(self):
        slow = Sleeper(10.0)
        sm = StateMachine(outcomes=['done', 'failed', 'preempted'])
        sm.add('SLOW', slow, transitions={'done': 'done', 'preempted': 'preempted', 'aborted': 'failed'}, timeout=0.1)
        t0 = time.monotonic()
        self.assertEqual(sm.execute(), 'failed')
        self.assertLess(time.monotonic() - t0, 1.0)
        self.assertEqual(slow.preempted, 1)
        # The next run is not affected by the old timeout.
        slow.duration = 0.0
        self.assertEqual(sm.execute(), 'done')

    def test_timeout_needs_an_aborted_transition(self):
        sm = StateMachine(outcomes=['done'])
        with self.assertRaises(InvalidTransitionError):
            sm.add('S', Sleeper(), transitions={'done': 'done', 'preempted': 'done'}, timeout=1.0)

    def test_callbacks_see_every_active_state(self):
        sm = StateMachine(outcomes=['done'])
        sm.add('A', Counter('n'), transitions={'n': 'B', 'preempted': 'done'})
        sm.add('B', Counter('n'), transitions={'n': 'done', 'preempted': 'done'})
        seen = []
        sm.register_transition_cb(lambda c, active: seen.append(list(active)))
        ends = []
        sm.register_termination_cb(lambda c, last, outcome: ends.append((last, outcome)))
        sm.execute()
        self.assertEqual(seen, [['A'], ['B'], []])
        self.assertEqual(ends, [(['B'], 'done')])


if __name__ == '__main__':
    unittest.main()
