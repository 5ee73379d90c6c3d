"""Every time in a match report is match time (scripts/match_report.py stamp_of): a message's
header stamp when it is on the bag's clock, the bag time when it is on another one (process_watch
probes on the wall clock and stamps its diagnostics with epoch seconds in a simulated match)."""
import os
import sys
import unittest

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
sys.path.insert(0, os.path.join(ROOT, 'scripts'))
from match_report import stamp_of  # noqa: E402


class Time(object):
    def __init__(self, t):
        self.t = t

    def to_sec(self):
        return self.t


class Header(object):
    def __init__(self, t):
        self.stamp = Time(t)


class Msg(object):
    def __init__(self, t=None):
        if t is not None:
            self.header = Header(t)


class ReportTimesTest(unittest.TestCase):
    def test_a_stamp_on_the_bags_clock_is_kept(self):
        self.assertEqual(stamp_of(Msg(52.25), Time(52.3)), 52.25)

    def test_a_wall_clock_stamp_in_a_simulated_match_is_replaced_by_the_bag_time(self):
        self.assertEqual(stamp_of(Msg(1795773675.2), Time(61.4)), 61.4)

    def test_no_stamp_or_zero_takes_the_bag_time(self):
        self.assertEqual(stamp_of(Msg(), Time(7.0)), 7.0)
        self.assertEqual(stamp_of(Msg(0.0), Time(7.0)), 7.0)

    def test_a_robot_on_the_wall_clock_keeps_its_stamps(self):
        self.assertEqual(stamp_of(Msg(1795773675.2), Time(1795773675.3)), 1795773675.2)


if __name__ == '__main__':
    unittest.main()
