"""The match strategies' knowledge and decisions (smart_brain/play, strategies/match_2009.py) without
ROS: where the columns are from what the camera sees, which task next, where goals were blocked;
a column pushed 15 cm from its configured spot is approached where it is; a hand that closed on
nothing does not go on to build."""
import math
import os
import unittest

import yaml

from smart_brain.play.blocked_spots import BlockedSpots
from smart_brain.play.element_tracker import ElementTracker
from smart_brain.play.task_cost import TaskCost
from smart_brain.statemachine import UserData, clock
from smart_brain.statemachine.userdata import Remapper

CHOOSE_2009 = ('approach', 'build_pose', 'away', 'look')  # CHOOSE's output keys, as the machine declares them
CHOOSE_2008 = ('path_points', 'away', 'look')


def window(data, outputs):
    """`data` as a CHOOSE state sees it: it may write its output keys, read none."""
    return Remapper(data, (), outputs)


CONFIG = os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..', 'config', 'eurobot2009.yaml')


class ElementTrackerTest(unittest.TestCase):
    def test_a_detection_moves_the_nearest_element_and_an_unseen_one_in_view_is_dropped(self):
        t = ElementTracker([(1.15, 1.05), (1.15, 0.8)], gate=0.12, forget_after=1.0, view=(0.4, 1.3, 0.4))
        robot = (0.5, 1.05, 0.0)  # looking east along y = 1.05: (1.15, 1.05) is in view, (1.15, 0.8) too
        t.update(0.0, robot, [(1.25, 1.06)])            # pushed 10 cm east
        self.assertEqual(sorted((round(x, 2), round(y, 2)) for x, y, _ in t.candidates()), [(1.15, 0.8), (1.25, 1.06)])
        for k in range(1, 7):                            # (1.15, 0.8) in view, never seen: gone after 1 s
            t.update(0.2 * k, robot, [(1.25, 1.06)])
        self.assertEqual([(round(x, 2), round(y, 2)) for x, y, _ in t.candidates()], [(1.25, 1.06)])

    def test_a_detection_far_from_every_element_adds_one_and_out_of_view_nothing_is_dropped(self):
        t = ElementTracker([(0.85, 0.55)], view=(0.4, 1.3, 0.4))
        t.update(0.0, (2.0, 1.5, math.pi), [(1.5, 1.5)])   # facing west: (0.85, 0.55) is out of view
        for k in range(1, 20):
            t.update(0.2 * k, (2.0, 1.5, math.pi), [])
        self.assertEqual(len(t.candidates()), 1)          # the new one was dropped (in view, unseen), the old kept
        self.assertEqual(t.candidates()[0][:2], (0.85, 0.55))

    def test_not_there_and_keep_out(self):
        t = ElementTracker([(1.15, 1.05), (1.5, 0.3)], keep_out=[(1.2, 0.0, 1.8, 0.6)])
        self.assertEqual([c[:2] for c in t.candidates()], [(1.15, 1.05)])  # the one in our temple is built
        t.not_there(1.16, 1.04)
        self.assertEqual(t.candidates(), [])


class TaskCostTest(unittest.TestCase):
    def test_cost_contest_and_time_left(self):
        c = TaskCost({'speed': 0.5, 'reserve': 2.0, 'contested_weight': 8.0}, our_side='left')
        self.assertAlmostEqual(c.seconds([(0, 0), (1, 0), (1, 1)], 3.0), 7.0)
        self.assertTrue(c.fits(7.0, 9.0))
        self.assertFalse(c.fits(7.5, 9.0))
        self.assertTrue(c.fits(100.0, None))
        self.assertEqual(c.contested(0.0, 1.0, 1.0), 0.0)
        self.assertEqual(c.contested(0.0, 2.0, 1.0), 0.5)   # their half
        c.met_opponent(0.0, 1.0, 1.0)
        self.assertEqual(c.contested(5.0, 1.1, 1.1), 1.0)
        c.met_opponent(6.0, 1.05, 1.0)
        self.assertEqual(c.contested(7.0, 1.1, 1.1), 2.0)   # twice blocked there weighs twice
        self.assertEqual(c.contested(60.0, 1.1, 1.1), 0.0)  # forgotten
        self.assertAlmostEqual(c.cost(0.0, 7.0, (1.0, 1.0), 3), 7.0 - 3.0)
        with self.assertRaises(ValueError):
            TaskCost({'nonsense': 1.0})


class BlockedSpotsTest(unittest.TestCase):
    def test_twice_near_the_same_spot_means_move_away_towards_the_middle(self):
        b = BlockedSpots(radius=0.15, memory=30.0, distance=0.35)
        b.note(0.0, (0.5, 0.5, 0.0))
        self.assertFalse(b.must_move_away(1.0, (0.5, 0.5, 0.0)))
        b.note(5.0, (0.55, 0.52, 0.0))
        self.assertTrue(b.must_move_away(6.0, (0.52, 0.5, 0.0)))
        self.assertFalse(b.must_move_away(6.0, (1.0, 1.0, 0.0)))   # elsewhere
        self.assertFalse(b.must_move_away(40.0, (0.52, 0.5, 0.0)))  # long ago
        x, y, _ = b.away_from((0.5, 0.5, 0.0))
        self.assertAlmostEqual(math.hypot(x - 0.5, y - 0.5), 0.35, places=6)
        self.assertGreater(x, 0.5)
        self.assertGreater(y, 0.5)
        b.note(7.0, (0.5, 0.5, 0.0))
        b.moved_away((0.5, 0.5, 0.0))
        self.assertFalse(b.must_move_away(8.0, (0.5, 0.5, 0.0)))


class _Result(object):
    def __init__(self, holding):
        self.holding = holding


class _HandState(object):
    def __init__(self, holding):
        self.result = _Result(holding)


def strategy2009(pose):
    """The 2009 strategy configured from config/eurobot2009.yaml (brain: match2009:), its pose fixed."""
    from smart_brain.strategies.match_2009 import Match2009Strategy
    with open(CONFIG) as f:
        config = yaml.safe_load(f)
    block = config['brain']['match2009']
    s = Match2009Strategy()
    s.configure(lambda k, d=None: block.get(k, d), (config['table']['length'], config['table']['width']),
                config['table']['score_zones'], our_side='left')
    s.pose = lambda: pose
    return s, block


class Match2009DecisionTest(unittest.TestCase):
    def test_a_column_pushed_15_cm_is_approached_where_it_is(self):
        robot = (0.35, 1.05, 0.0)
        s, block = strategy2009(robot)
        configured = tuple(block['columns'][2])                 # (0.85, 1.05), 0.5 m ahead of the robot
        pushed = (configured[0] + 0.15, configured[1])
        s.tracker.elements = [e for e in s.tracker.elements if (e.x, e.y) == configured]  # the one column
        for k in range(7):                                       # the camera at 5 Hz for 1.2 s
            s.tracker.update(0.2 * k, robot, [pushed])
        self.assertEqual([c[:2] for c in s.tracker.candidates()], [pushed])
        data = UserData(approach=None, build_pose=None, away=None, look=None)
        ud = window(data, CHOOSE_2009)
        self.assertEqual(s.choose(ud), 'take')
        self.assertEqual(s.target, pushed)
        ax, ay, heading = data.approach
        self.assertAlmostEqual(math.hypot(pushed[0] - ax, pushed[1] - ay), block['approach'])
        self.assertAlmostEqual(heading, math.atan2(pushed[1] - ay, pushed[0] - ax))

    def test_a_hand_that_closed_on_nothing_does_not_go_on_to_build(self):
        s, block = strategy2009((1.0, 1.3, -math.pi / 2))
        data = UserData(approach=None, build_pose=None, away=None, look=None)
        ud = window(data, CHOOSE_2009)
        self.assertEqual(s.choose(ud), 'take')
        target = s.target
        s.close_state = _HandState(0)
        self.assertEqual(s.check_held(ud), 'empty')
        self.assertEqual(s.held, 0)
        self.assertNotIn(target, [c[:2] for c in s.tracker.candidates()])  # not where it was believed
        self.assertEqual(s.choose(ud), 'take')                              # another column, not a build
        self.assertNotEqual(s.target, target)
        s.close_state = _HandState(1)
        self.assertEqual(s.check_held(ud), 'held')
        self.assertEqual(s.held, 1)
        self.assertEqual(s.choose(ud), 'build')
        self.assertEqual(len(data.build_pose), 3)

    def test_the_last_seconds_go_to_a_task_that_can_finish(self):
        s, _ = strategy2009((0.5, 1.3, 0.0))
        ud = window(UserData(approach=None, build_pose=None, away=None, look=None), CHOOSE_2009)
        s.time_left = 3.0     # no take-and-build fits in 3 s: no column is taken (a lookout at most)
        self.assertIn(s.choose(ud), ('none', 'look'))
        self.assertIsNone(s.target)
        s.held = 1
        s.time_left = 60.0
        self.assertEqual(s.choose(ud), 'build')


if __name__ == '__main__':
    unittest.main()


LOGION = os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..', 'config', 'logion.yaml')


def strategy2008(pose):
    """Logion's 2008 strategy configured from config/logion.yaml (brain: match2008:), its pose fixed."""
    from smart_brain.strategies.match_2008 import Match2008Strategy
    with open(LOGION) as f:
        config = yaml.safe_load(f)
    block = config['brain']['match2008']
    t = config['table']
    s = Match2008Strategy()
    s.configure(lambda k, d=None: block.get(k, d), (t['length'], t['width']), t['elements'], t['score_zones'],
                our_colour='red')
    s.pose = lambda: pose
    return s, block


class Match2009MoreDecisionsTest(unittest.TestCase):
    def test_blocked_twice_here_it_moves_away_and_with_nothing_known_it_looks(self):
        s, block = strategy2009((0.9, 0.9, 0.0))
        data = UserData(approach=None, build_pose=None, away=None, look=None)
        ud = window(data, CHOOSE_2009)
        now = clock.now()  # the strategy's clock
        s.blocked.note(now - 5.0, (0.9, 0.9, 0.0))
        s.blocked.note(now - 1.0, (0.92, 0.9, 0.0))
        self.assertEqual(s.choose(ud), 'away')
        self.assertEqual(len(data.away), 3)
        s.blocked.moved_away((0.9, 0.9, 0.0))
        s.tracker.elements = []  # nothing known
        self.assertEqual(s.choose(ud), 'look')
        self.assertIn(list(data.look), [list(map(float, p)) for p in block['look_from']])


class Match2008DecisionTest(unittest.TestCase):
    def test_a_trip_takes_the_most_points_per_second_and_fits_the_time_left(self):
        s, block = strategy2008((0.25, 1.8, -math.pi / 2))
        self.assertEqual(s.points, {'ball_red': 3, 'ball_white': 1})
        ud = window(UserData(path_points=[], away=None, look=[]), CHOOSE_2008)
        self.assertEqual(s.choose(ud), 'harvest')
        self.assertGreaterEqual(len(s.path), 1)
        self.assertLessEqual(len(s.path), block['max_balls'])
        self.assertEqual(s.path[0][0], 'ball_red')  # a red ball (3 points) before a white one (1)
        s.time_left = 4.0                            # no trip fits: nothing held, nothing to deliver
        self.assertIn(s.choose(ud), ('none', 'search'))

    def test_what_is_held_is_counted_not_the_balls_driven_through(self):
        s, _ = strategy2008((1.0, 1.0, 0.0))
        ud = window(UserData(path_points=[], away=None, look=[]), CHOOSE_2008)
        self.assertEqual(s.choose(ud), 'harvest')
        s.harvested(ud)            # the trip swallowed nothing (the throat sensor counted none)
        s.held = 0
        s.trackers = {k: ElementTracker([]) for k in s.trackers}  # and nothing else is known
        self.assertNotEqual(s.choose(ud), 'deliver')
        s.held = 2                 # two counted in: delivered
        self.assertEqual(s.choose(ud), 'deliver')
