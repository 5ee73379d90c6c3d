"""scripts/scoreboard.py (`make play`) on a made-up `make matches` run: the table read back, the
figures and their 95 % intervals, and each target met or how far off. No ROS, no simulation."""
import math
import os
import tempfile
import unittest

import yaml

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
from robot_tools.matches import scoreboard

# As run_matches.py writes it (its table_lines and closing_line).
RUN = """seed opponent    ours  opp result contacts triggers stuck stalls in_contact false_alarms loc_rmse_m loc_max_m idle_s idle_max_s eff_off_s wall_s
   1 random_walk   10    0    won        0        5     0      0          0            0     0.0021    0.0073   15.1        3.3     0.020     50
   2 route         12    0    won        0        3     0      1          0            0     0.0031    0.0110   11.5        4.5    -0.063     47
   3 blocker        0    0   draw        0        1     0      2          0            0     0.0022    0.0092   14.3        7.6     0.000     50
   4 player        13   15   lost        0        4     2      0          0            0     0.0025    0.0067   10.3        4.6     0.000     49
   5 random_walk    -    -      -        -        -     -      -          -            -          -         -      -          -         -      -
   6 route         15    0    won        1        8     0      0          0            0     0.0028    0.0083   19.1        5.9    -0.011     54
   7 blocker        6    0    won        0        1     0      0          0            0     0.0019    0.0095    7.9        4.6    -0.024     54
   8 player        16   12    won        0        1     0      0          0            0     0.0027    0.0082    4.7        1.9     0.008     55
violation: seed 5: the match never started
summary: /tmp/x/eurobot2009_matches.png
cluster: 1 workers, 0 retries
wins 5 losses 1 draws 1
matches 8 score_mean 10.29 score_min 0 violations 1 wall_s 431 factor 0
"""


class ScoreboardTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix='scoreboard_')
        self.table = os.path.join(self.dir, 'eurobot2009_matches.txt')
        with open(self.table, 'w') as f:
            f.write(RUN)

    def test_the_table_is_read_back_with_its_violations(self):
        rows, violations = scoreboard.read_table(self.table)
        self.assertEqual([int(r['seed']) for r in rows], list(range(1, 9)))
        self.assertEqual(violations, 1)
        self.assertIsNone(rows[4]['ours'], 'a match without a score has none')
        self.assertEqual(rows[3]['opponent'], 'player')
        self.assertEqual(rows[7]['result'], 'won')

    def test_not_a_summary_is_refused(self):
        with open(self.table, 'w') as f:
            f.write('seed opponent ours\n')
        with self.assertRaises(ValueError):
            scoreboard.read_table(self.table)

    def test_figures_and_intervals(self):
        rows, violations = scoreboard.read_table(self.table)
        found = scoreboard.figures(rows, violations)
        mean, low, high, _ = found['score_mean']
        scores = [10, 12, 0, 13, 15, 6, 16]  # the unscored match left out
        self.assertAlmostEqual(mean, sum(scores) / 7.0)
        self.assertLess(low, mean)
        self.assertGreater(high, mean)
        self.assertAlmostEqual(mean - low, high - mean)
        self.assertEqual(found['zero_scores'][0], 1)
        rate, rlow, rhigh, detail = found['win_rate_player']
        self.assertEqual((rate, detail), (0.5, '1 of 2'))
        self.assertTrue(0.0 < rlow < 0.5 < rhigh < 1.0)
        self.assertAlmostEqual(found['stalls_per_match'][0], 3 / 8.0, msg='a match with no figure counts 0 stalls')
        self.assertEqual(found['violations'][0], 1)

    def test_wilson_at_all_and_none(self):
        rate, low, high = scoreboard.wilson_interval(10, 10)
        self.assertEqual(rate, 1.0)
        self.assertAlmostEqual(high, 1.0)
        self.assertAlmostEqual(low, 0.722, places=3)
        rate, low, high = scoreboard.wilson_interval(0, 10)
        self.assertEqual(rate, 0.0)
        self.assertAlmostEqual(low, 0.0)
        self.assertTrue(math.isnan(scoreboard.wilson_interval(0, 0)[0]))

    def test_targets_met_or_how_far_off(self):
        self.assertEqual(scoreboard.verdict('score_mean', 12.5, 12, True), 'met')
        self.assertEqual(scoreboard.verdict('score_mean', 10.25, 12, True), 'short by 1.75')
        self.assertEqual(scoreboard.verdict('idle_per_match', 6.5, 5.0, False), 'short by 1.50')
        self.assertEqual(scoreboard.verdict('win_rate_player', 0.5, 0.9, True), 'short by 40 points')
        self.assertEqual(scoreboard.verdict('zero_scores', 0, 0, False), 'met')
        self.assertEqual(scoreboard.verdict('score_mean', 3.0, None, True), 'no target')

    def test_every_robot_with_a_match_has_targets_and_every_target_is_a_figure(self):
        with open(scoreboard.TARGETS) as f:
            targets = yaml.safe_load(f)
        figures = {name for name, _, _ in scoreboard.FIGURES}
        for robot, block in targets.items():
            self.assertTrue(os.path.exists(os.path.join(ROOT, 'launch', robot + '.launch')), robot)
            self.assertLessEqual(set(block), figures, robot)
        self.assertEqual(set(targets), {'eurobot2009', 'logion'})

    def test_the_lines_say_each_figure_against_its_target(self):
        rows, violations = scoreboard.read_table(self.table)
        lines, met, judged = scoreboard.board_lines('eurobot2009', rows, violations,
                                                    {'score_mean': 12, 'zero_scores': 0, 'violations': 0})
        self.assertEqual(judged, 3)
        self.assertEqual(met, 0)
        text = '\n'.join(lines)
        self.assertIn('our score', text)
        self.assertIn('(target >= 12): short by', text)
        self.assertIn('win rate vs player   50% ci95 [', text)
        self.assertIn('no target', text)


if __name__ == '__main__':
    unittest.main()
