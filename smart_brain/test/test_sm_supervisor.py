"""Supervisor: triggers preempt the body, handlers decide resume / restart / goto / abort; debounce."""
import threading
import time
import unittest

import os  # noqa: E402
import sys  # noqa: E402

# catkin runs nose without adding this folder to the path; the shared helpers live here.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sm_helpers import Counter, Sleeper
from smart_brain.statemachine import CBState, Runner, StateMachine, Supervisor, Trigger


class Flag(object):
    def __init__(self):
        self.value = False

    def __call__(self):
        return self.value


def body_machine(work):
    first, last = Counter('done'), Counter('done')
    sm = StateMachine(outcomes=['done', 'preempted'])
    sm.add('FIRST', first, transitions={'done': 'WORK', 'preempted': 'preempted'})
    sm.add('WORK', work, transitions={'done': 'LAST', 'preempted': 'preempted'})
    sm.add('LAST', last, transitions={'done': 'done', 'preempted': 'preempted'})
    return sm, first, last


def handler(decision, flag=None):
    def cb(ud):
        if flag is not None:
            flag.value = False   # the handler cleared the obstacle
        return decision
    return CBState(cb, outcomes=[decision])


class SupervisorTest(unittest.TestCase):
    def run_with_trigger(self, decision, work_duration=0.3):
        work = Sleeper(work_duration)
        sm, first, last = body_machine(work)
        flag = Flag()
        trig = Trigger('obstacle', flag, handler(decision, flag), debounce=0.0)
        sup = Supervisor(sm, [trig])
        runner = Runner('sup')
        runner.start(sup)
        self.assertTrue(work.started.wait(2.0))
        flag.value = True
        self.assertTrue(runner.wait(5.0))
        return runner.outcome, first, work, last, trig

    def test_resume_reenters_the_interrupted_state(self):
        outcome, first, work, last, trig = self.run_with_trigger('resume')
        self.assertEqual(outcome, 'done')
        self.assertEqual(trig.fired, 1)
        self.assertEqual((first.runs, work.runs, work.preempted, last.runs), (1, 2, 1, 1))

    def test_restart_starts_from_the_initial_state(self):
        outcome, first, work, last, _ = self.run_with_trigger('restart')
        self.assertEqual(outcome, 'done')
        self.assertEqual((first.runs, work.runs, last.runs), (2, 2, 1))

    def test_goto_jumps_to_the_named_state(self):
        outcome, first, work, last, _ = self.run_with_trigger('LAST')
        self.assertEqual(outcome, 'done')
        self.assertEqual((first.runs, work.runs, last.runs), (1, 1, 1))
        self.assertEqual(work.preempted, 1)

    def test_abort_ends_the_supervisor(self):
        outcome, first, work, last, _ = self.run_with_trigger('aborted')
        self.assertEqual(outcome, 'aborted')
        self.assertEqual(last.runs, 0)

    def test_deep_history_resumes_inside_nested_machines(self):
        work = Sleeper(0.3)
        inner, inner_first, _ = body_machine(work)
        outer = StateMachine(outcomes=['done', 'preempted'])
        before = Counter('done')
        outer.add('BEFORE', before, transitions={'done': 'INNER', 'preempted': 'preempted'})
        outer.add('INNER', inner, transitions={'done': 'done', 'preempted': 'preempted'})
        flag = Flag()
        sup = Supervisor(outer, [Trigger('t', flag, handler('resume', flag))])
        runner = Runner('sup')
        runner.start(sup)
        work.started.wait(2.0)
        flag.value = True
        runner.wait(5.0)
        self.assertEqual(runner.outcome, 'done')
        self.assertEqual((before.runs, inner_first.runs, work.runs), (1, 1, 2))

    def test_debounce_ignores_short_blips(self):
        work = Sleeper(0.6)
        sm, _, _ = body_machine(work)
        flag = Flag()
        trig = Trigger('blip', flag, handler('resume', flag), debounce=0.15)
        sup = Supervisor(sm, [trig])
        runner = Runner('sup')
        runner.start(sup)
        work.started.wait(2.0)
        for _ in range(3):      # 50 ms blips, shorter than the debounce
            flag.value = True
            time.sleep(0.05)
            flag.value = False
            time.sleep(0.05)
        runner.wait(5.0)
        self.assertEqual(trig.fired, 0)
        self.assertEqual(work.preempted, 0)

    def test_holdoff_limits_refiring_of_a_stuck_condition(self):
        work = Sleeper(0.5)
        sm, _, _ = body_machine(work)
        trig = Trigger('stuck', lambda: True, handler('resume'), debounce=0.0, holdoff=0.2)
        sup = Supervisor(sm, [trig])
        runner = Runner('sup')
        t0 = time.monotonic()
        runner.start(sup)
        time.sleep(1.0)
        runner.preempt()
        self.assertTrue(runner.wait(2.0))
        self.assertEqual(runner.outcome, 'preempted')
        # at most one firing per holdoff period
        self.assertLessEqual(trig.fired, int((time.monotonic() - t0) / 0.2) + 1)
        self.assertGreaterEqual(trig.fired, 3)

    def test_trigger_reaction_is_prompt(self):
        work = Sleeper(10.0)
        sm, _, _ = body_machine(work)
        flag = Flag()
        handled = threading.Event()

        def cb(ud):
            handled.set()
            flag.value = False
            return 'aborted'
        sup = Supervisor(sm, [Trigger('t', flag, CBState(cb, outcomes=['aborted']))])
        runner = Runner('sup')
        runner.start(sup)
        work.started.wait(2.0)
        t0 = time.monotonic()
        flag.value = True
        self.assertTrue(handled.wait(1.0))
        self.assertLess(time.monotonic() - t0, 0.1)
        runner.wait(2.0)


if __name__ == '__main__':
    unittest.main()


class Outcomes(CBState):
    """Ends with the next outcome of a script (the last one repeats), counting its runs."""

    def __init__(self, script):
        self.script = list(script)
        self.runs = 0
        CBState.__init__(self, self._next, outcomes=sorted(set(self.script)))

    def _next(self, ud):
        self.runs += 1
        return self.script[min(self.runs, len(self.script)) - 1]


def task_machine(task):
    sm = StateMachine(outcomes=['succeeded', 'aborted', 'preempted'])
    sm.add('TASK', task, transitions={o: o for o in task.get_registered_outcomes()})
    return sm


class KeepPlayingTest(unittest.TestCase):
    """restart_on: a strategy gives up on a task, not on the match. The brain's clock in these
    tests is the monotonic one (clock.py's default off ROS), so back-offs are timed on it."""

    def test_an_aborted_body_starts_again_after_a_growing_back_off(self):
        task = Outcomes(['aborted', 'aborted', 'aborted', 'succeeded'])
        sup = Supervisor(task_machine(task), restart_on=('aborted',), backoff=(0.05, 0.4))
        t0 = time.monotonic()
        runner = Runner('sup')
        runner.start(sup)
        self.assertTrue(runner.wait(5.0))
        self.assertEqual(runner.outcome, 'succeeded')
        self.assertEqual((task.runs, sup.restarts), (4, 3))
        # Back-offs 0.05, 0.1, 0.2: the body ends at once each time, so each one doubles.
        self.assertGreaterEqual(time.monotonic() - t0, 0.35)
        notes = [what for _, what in sup.log]
        self.assertIn('body ended aborted: starting it again in 0.1 s', notes)
        self.assertIn('body ended aborted: starting it again in 0.2 s', notes)

    def test_before_restart_can_say_nothing_is_left(self):
        task = Outcomes(['aborted'])
        asked = []

        def before_restart(outcome):
            asked.append(outcome)
            return len(asked) < 3

        sup = Supervisor(task_machine(task), restart_on=('aborted',), backoff=(0.0, 0.0), before_restart=before_restart)
        runner = Runner('sup')
        runner.start(sup)
        self.assertTrue(runner.wait(5.0))
        self.assertEqual(runner.outcome, 'aborted')
        self.assertEqual((task.runs, asked), (3, ['aborted'] * 3))

    def test_nothing_found_starts_again_at_once(self):
        # 'succeeded' listed (nothing left now: look again): no back-off after a run longer than
        # the first back-off, the first back-off after a shorter one (no busy loop).
        starts = []

        def look(ud):
            starts.append(time.monotonic())
            time.sleep(0.1 if len(starts) < 3 else 0.0)
            return 'succeeded' if len(starts) < 5 else 'aborted'

        task = CBState(look, outcomes=['succeeded', 'aborted'])
        sup = Supervisor(task_machine(task), restart_on=('succeeded',), backoff=(0.05, 1.0))
        runner = Runner('sup')
        runner.start(sup)
        self.assertTrue(runner.wait(5.0))
        self.assertEqual((runner.outcome, len(starts)), ('aborted', 5))
        gaps = [b - a for a, b in zip(starts, starts[1:])]
        self.assertLess(gaps[0] - 0.1, 0.045)        # at once after a 0.1 s run
        self.assertGreaterEqual(gaps[3], 0.05)       # after a run of 0 s: the first back-off

    def test_outcomes_not_listed_end_the_supervisor(self):
        task = Outcomes(['succeeded'])
        sup = Supervisor(task_machine(task), restart_on=('aborted',))
        runner = Runner('sup')
        runner.start(sup)
        self.assertTrue(runner.wait(5.0))
        self.assertEqual((runner.outcome, task.runs, sup.restarts), ('succeeded', 1, 0))

    def test_a_handler_that_aborts_is_restarted_too(self):
        work = Sleeper(0.3)
        sm, first, _ = body_machine(work)
        flag = Flag()
        sup = Supervisor(sm, [Trigger('obstacle', flag, handler('aborted', flag), debounce=0.0)],
                         restart_on=('aborted',), backoff=(0.05, 0.05))
        runner = Runner('sup')
        runner.start(sup)
        self.assertTrue(work.started.wait(2.0))
        flag.value = True
        self.assertTrue(runner.wait(5.0))
        self.assertEqual(runner.outcome, 'done')
        self.assertEqual((first.runs, sup.restarts), (2, 1))

    def test_a_preempt_during_the_back_off_ends_at_once(self):
        task = Outcomes(['aborted'])
        sup = Supervisor(task_machine(task), restart_on=('aborted',), backoff=(30.0, 30.0))
        runner = Runner('sup')
        runner.start(sup)
        deadline = time.monotonic() + 2.0
        while task.runs == 0 and time.monotonic() < deadline:
            time.sleep(0.01)
        time.sleep(0.1)
        t0 = time.monotonic()
        runner.preempt()
        self.assertTrue(runner.wait(2.0))
        self.assertEqual(runner.outcome, 'preempted')
        self.assertLess(time.monotonic() - t0, 1.0)

    def test_a_bad_back_off_is_refused(self):
        with self.assertRaises(ValueError):
            Supervisor(task_machine(Outcomes(['aborted'])), restart_on=('aborted',), backoff=(2.0, 1.0))
