"""Every time in a match report is match time (robot_tools.report.match_bag stamp_of): a message's
header stamp when it is on the bag's clock, the bag time when it is on another one (process_watch
probes on the wall clock and stamps its diagnostics with epoch seconds in a simulated match); and a
goal that never ended does not stop the report's goal spans."""
import os
import unittest
from types import SimpleNamespace

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
from robot_tools.report.match_bag import Match, stamp_of


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


def goal(gid):
    return SimpleNamespace(goal_id=SimpleNamespace(id=gid))


def result(gid):
    return SimpleNamespace(status=goal(gid))


class GoalBag(object):
    """What Match.hal_goal_spans reads: one action's goals and results, (message, bag time)."""

    def __init__(self, goals, results):
        self.topics = {'/hal/driver/goto/goal': goals, '/hal/driver/goto/result': results}

    def find(self, prefix, suffix):
        return [t for t in self.topics if t.startswith(prefix) and t.endswith(suffix)]

    def has(self, topic):
        return topic in self.topics

    def read(self, topic):
        return [(topic, msg, Time(t)) for msg, t in self.topics[topic]]


class GoalSpansTest(unittest.TestCase):
    def test_a_goal_that_never_ended_beside_one_sent_at_the_same_time(self):
        # The HAL killed mid-goal: its goal has no result (a chaos match's report stopped here).
        bag = GoalBag([(goal('a'), 12.0), (goal('b'), 12.0), (goal('c'), 3.0)],
                      [(result('b'), 14.5), (result('c'), 5.0)])
        self.assertEqual(Match.hal_goal_spans(bag), [(3.0, 5.0), (12.0, 14.5), (12.0, None)])


if __name__ == '__main__':
    unittest.main()
