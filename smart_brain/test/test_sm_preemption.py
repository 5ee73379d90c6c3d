"""Preemption through nested containers: prompt, consumed exactly once, never sticky."""
import time
import unittest

import os  # noqa: E402
import sys  # noqa: E402

# catkin runs nose without adding this folder to the path; the shared helpers live here.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sm_helpers import Counter, Sleeper, Stubborn
from smart_brain.statemachine import Concurrence, Runner, StateMachine, State


def nested(leaf):
    inner = StateMachine(outcomes=['done', 'preempted'])
    inner.add('LEAF', leaf, transitions={'done': 'done', 'preempted': 'preempted'})
    middle = StateMachine(outcomes=['done', 'preempted'])
    middle.add('INNER', inner, transitions={'done': 'done', 'preempted': 'preempted'})
    top = StateMachine(outcomes=['done', 'preempted'])
    top.add('MIDDLE', middle, transitions={'done': 'AFTER', 'preempted': 'preempted'})
    top.add('AFTER', Counter('done'), transitions={'done': 'done', 'preempted': 'preempted'})
    return top


class PreemptionTest(unittest.TestCase):
    def test_preempt_reaches_the_leaf_of_a_nested_machine_promptly(self):
        leaf = Sleeper(10.0)
        top = nested(leaf)
        runner = Runner('t')
        runner.start(top)
        self.assertTrue(leaf.started.wait(2.0))
        t0 = time.monotonic()
        self.assertTrue(runner.preempt())
        self.assertTrue(runner.wait(2.0))
        self.assertLess(time.monotonic() - t0, 0.1)
        self.assertEqual(runner.outcome, 'preempted')
        self.assertEqual(leaf.preempted, 1)
        self.assertEqual(top['AFTER'].runs, 0)

    def test_a_preempt_is_not_sticky(self):
        leaf = Sleeper(10.0)
        top = nested(leaf)
        runner = Runner('t')
        runner.start(top)
        leaf.started.wait(2.0)
        runner.preempt()
        runner.wait(2.0)
        # Run again: it must run to the end, not be preempted by the old request.
        leaf.duration = 0.05
        leaf.started.clear()
        runner.start(top)
        self.assertTrue(runner.wait(2.0))
        self.assertEqual(runner.outcome, 'done')
        self.assertEqual(top['AFTER'].runs, 1)

    def test_a_preempt_while_idle_is_dropped(self):
        top = nested(Sleeper(0.01))
        self.assertFalse(top.request_preempt())
        self.assertEqual(top.execute(), 'done')

    def test_a_late_preempt_still_stops_the_machine_once(self):
        # The leaf ignores the request and finishes 'done': the machine, not the leaf,
        # consumes the preempt, and the next state does not run.
        stubborn = Stubborn(0.2)
        top = StateMachine(outcomes=['done', 'preempted'])
        top.add('STUBBORN', stubborn, transitions={'done': 'NEXT', 'preempted': 'preempted'})
        top.add('NEXT', Counter('done'), transitions={'done': 'done', 'preempted': 'preempted'})
        runner = Runner('t')
        runner.start(top)
        stubborn.started.wait(2.0)
        runner.preempt()
        runner.wait(2.0)
        self.assertEqual(runner.outcome, 'preempted')
        self.assertEqual(top['NEXT'].runs, 0)
        self.assertFalse(top.preempt_requested())
        self.assertFalse(stubborn.preempt_requested())

    def test_preempt_right_after_start_is_not_lost(self):
        for _ in range(50):
            leaf = Sleeper(10.0)
            top = nested(leaf)
            runner = Runner('t')
            runner.start(top)
            self.assertTrue(runner.preempt())
            self.assertTrue(runner.wait(2.0))
            self.assertEqual(runner.outcome, 'preempted')

    def test_concurrence_preempted_says_preempted(self):
        a, b = Sleeper(10.0), Sleeper(10.0)
        cc = Concurrence(outcomes=['done', 'preempted'], default_outcome='done')
        cc.add('A', a)
        cc.add('B', b)
        top = StateMachine(outcomes=['done', 'preempted'])
        top.add('CC', cc, transitions={'done': 'done', 'preempted': 'preempted'})
        runner = Runner('t')
        runner.start(top)
        a.started.wait(2.0)
        b.started.wait(2.0)
        t0 = time.monotonic()
        runner.preempt()
        self.assertTrue(runner.wait(2.0))
        self.assertLess(time.monotonic() - t0, 0.2)
        self.assertEqual(runner.outcome, 'preempted')
        self.assertEqual((a.preempted, b.preempted), (1, 1))

    def test_user_errors_surface_in_the_caller(self):
        class Broken(State):
            def __init__(self):
                State.__init__(self, outcomes=['x'])

            def execute(self, ud):
                raise ValueError('boom')
        sm = StateMachine(outcomes=['x'])
        sm.add('B', Broken(), transitions={'x': 'x'})
        runner = Runner('t')
        runner.start(sm)
        runner.wait(2.0)
        self.assertIsNone(runner.outcome)
        self.assertIn('boom', str(runner.error))


if __name__ == '__main__':
    unittest.main()
