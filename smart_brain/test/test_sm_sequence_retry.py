"""Sequence (states in the order added) and Retry (again while 'aborted')."""
import unittest

import os  # noqa: E402
import sys  # noqa: E402

# catkin runs nose without adding this folder to the path; the shared helpers live here.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sm_helpers import Counter
from smart_brain.statemachine import CBState, Retry, Sequence, StateMachine


class SequenceRetryTest(unittest.TestCase):
    def test_sequence_runs_in_order_and_stops_on_other_outcomes(self):
        order = []

        def step(name, outcome='succeeded'):
            def cb(ud):
                order.append(name)
                return outcome
            return CBState(cb, outcomes=['succeeded', 'aborted'])
        seq = Sequence(outcomes=['succeeded', 'aborted'], connector_outcome='succeeded')
        with seq:
            Sequence.add('A', step('A'))
            Sequence.add('B', step('B'))
            Sequence.add('C', step('C'))
        self.assertEqual(seq.execute(), 'succeeded')
        self.assertEqual(order, ['A', 'B', 'C'])
        order[:] = []
        seq2 = Sequence(outcomes=['succeeded', 'aborted'], connector_outcome='succeeded')
        seq2.add('A', step('A'))
        seq2.add('B', step('B', 'aborted'))
        seq2.add('C', step('C'))
        self.assertEqual(seq2.execute(), 'aborted')
        self.assertEqual(order, ['A', 'B'])

    def test_retry_until_success_or_attempts(self):
        results = iter(['aborted', 'aborted', 'succeeded'])
        flaky = CBState(lambda ud: next(results), outcomes=['succeeded', 'aborted'])
        r = Retry(flaky, attempts=3)
        self.assertEqual(r.run(None), 'succeeded')
        self.assertEqual(r.tries, 3)
        always = Counter('aborted')
        r = Retry(always, attempts=2)
        self.assertEqual(r.run(None), 'aborted')
        self.assertEqual(always.runs, 2)

    def test_retry_inside_a_machine(self):
        sm = StateMachine(outcomes=['ok', 'failed'])
        results = iter(['aborted', 'succeeded'])
        sm.add('TRY', Retry(CBState(lambda ud: next(results), outcomes=['succeeded', 'aborted'])),
               transitions={'succeeded': 'ok', 'aborted': 'failed'})
        self.assertEqual(sm.execute(), 'ok')


if __name__ == '__main__':
    unittest.main()
