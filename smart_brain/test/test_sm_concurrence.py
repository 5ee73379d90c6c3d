"""Concurrence: outcome maps, outcome_cb, default outcome, child termination."""
import time
import unittest

import os  # noqa: E402
import sys  # noqa: E402

# catkin runs nose without adding this folder to the path; the shared helpers live here.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sm_helpers import Counter, Sleeper
from smart_brain.statemachine import CBState, Concurrence, InvalidTransitionError, StateMachine


class ConcurrenceTest(unittest.TestCase):
    def build(self, a, b, **kw):
        cc = Concurrence(outcomes=['both', 'either', 'neither', 'preempted'], default_outcome='neither', **kw)
        cc.add('A', a)
        cc.add('B', b)
        return cc

    def test_outcome_map_first_full_match_wins(self):
        omap = {'both': {'A': 'yes', 'B': 'yes'}, 'either': {'A': 'yes'}}
        self.assertEqual(self.build(Counter('yes', ['no']), Counter('yes', ['no']), outcome_map=omap).execute(), 'both')
        self.assertEqual(self.build(Counter('yes', ['no']), Counter('no', ['yes']), outcome_map=omap).execute(), 'either')
        self.assertEqual(self.build(Counter('no', ['yes']), Counter('yes', ['no']), outcome_map=omap).execute(), 'neither')

    def test_outcome_cb_decides_when_no_map_matches(self):
        cc = self.build(Counter('yes'), Counter('yes'), outcome_cb=lambda res: 'either' if 'yes' in res.values() else None)
        self.assertEqual(cc.execute(), 'either')

    def test_children_run_at_the_same_time(self):
        a, b = Sleeper(0.3), Sleeper(0.3)
        t0 = time.monotonic()
        self.build(a, b).execute()
        self.assertLess(time.monotonic() - t0, 0.5)

    def test_child_termination_preempts_the_others(self):
        fast, slow = Counter('yes'), Sleeper(10.0)
        cc = self.build(fast, slow, outcome_map={'either': {'A': 'yes', 'B': 'preempted'}},
                        child_termination_cb=lambda res: res.get('A') == 'yes')
        t0 = time.monotonic()
        self.assertEqual(cc.execute(), 'either')
        self.assertLess(time.monotonic() - t0, 0.5)
        self.assertEqual(slow.preempted, 1)

    def test_userdata_is_shared_through_remapping(self):
        def put(ud):
            ud.out = 7
            return 'yes'
        cc = Concurrence(outcomes=['done'], default_outcome='done', output_keys=['seven'])
        cc.add('PUT', CBState(put, outcomes=['yes'], output_keys=['out']), remapping={'out': 'seven'})
        sm = StateMachine(outcomes=['done'])
        sm.add('CC', cc, transitions={'done': 'done'})
        sm.execute()
        self.assertEqual(sm.userdata.seven, 7)

    def test_bad_outcome_map_is_refused(self):
        with self.assertRaises(InvalidTransitionError):
            self.build(Counter('yes'), Counter('yes'), outcome_map={'both': {'C': 'yes'}}).check_consistency()
        with self.assertRaises(InvalidTransitionError):
            self.build(Counter('yes'), Counter('yes'), outcome_map={'both': {'A': 'nope'}}).check_consistency()


if __name__ == '__main__':
    unittest.main()
