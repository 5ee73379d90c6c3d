"""`make play`: the scoreboard. How well each robot plays, over many matches, against its targets.

    scripts/scoreboard.py [--robots eurobot2009,logion] [--n 20] [--seed 1] [--factor 0]
                          [--judge ROBOT=DIR ...]

For each robot, `make matches` (scripts/run_matches.py: N matches, seeds SEED.., the opponent
cycle random_walk, route, blocker, player) in a folder of its own, then its figures from the
table that run wrote (DIR/ROBOT_matches.txt), each against the robot's targets in
config/scoreboard.yaml:
  score_mean         our mean score, with its 95 % interval (Student's t over the matches)
  zero_scores        matches where we scored 0
  win_rate_player    wins against the `player` opponent, with its 95 % interval (Wilson's)
  stalls_per_match   driver goals ended by a stall, per match, with its 95 % interval
  idle_per_match     [s] idle while the match ran, per match, with its 95 % interval
  violations         broken invariants over all the matches
A target is met when the figure is (a mean: its estimate, not its interval); otherwise the line
says how far off it is. --judge ROBOT=DIR judges a run of run_matches.py already made. The last
line is
    scoreboard: robots R matches M targets_met T of K
and the exit code is 0 when every robot's matches ran (met or not: this is a benchmark), 1 when a
run gave no table.
"""
import argparse
import math
import os
import subprocess
import sys

import yaml

from robot_tools.tuning.objective import mean_interval

from robot_tools.paths import ROOT
TARGETS = os.path.join(ROOT, 'config', 'scoreboard.yaml')
#: (figure, what it is, at_least): the order of the lines.
FIGURES = (('score_mean', 'our score', True), ('zero_scores', 'matches with 0', False),
           ('win_rate_player', 'win rate vs player', True), ('stalls_per_match', 'stalls per match', False),
           ('idle_per_match', 'idle per match [s]', False), ('violations', 'violations', False))


def read_table(path):
    """(rows as dicts of the table's columns, violation count) of a run_matches.py summary.
    Numbers are floats, '-' (no value) is None."""
    rows, violations, header = [], None, None
    with open(path) as f:
        for line in f:
            cells = line.split()
            if not cells:
                continue
            if cells[0] == 'seed':
                header = cells
            elif header and len(cells) == len(header) and cells[0].isdigit():
                rows.append({name: cell if name in ('opponent', 'result') else (None if cell == '-' else float(cell))
                             for name, cell in zip(header, cells)})
            elif cells[0] == 'matches' and 'violations' in cells:
                violations = int(cells[cells.index('violations') + 1])
    if header is None or violations is None:
        raise ValueError('%s is not a run_matches.py summary (no table or no closing line)' % path)
    return rows, violations


def wilson_interval(successes, n):
    """(rate, low, high): Wilson's 95 % interval of a proportion (sound at 0 or n of n too)."""
    if n == 0:
        return float('nan'), float('nan'), float('nan')
    z = 1.959963984540054
    p = successes / float(n)
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4.0 * n * n)) / (1 + z * z / n)
    return p, max(0.0, centre - half), min(1.0, centre + half)


def figures(rows, violations):
    """{figure: (value, low, high, detail)} of one robot's matches (low/high None: no interval)."""
    scored = [r for r in rows if r['ours'] is not None]
    player = [r for r in scored if r['opponent'] == 'player']
    wins = sum(1 for r in player if r['result'] == 'won')
    out = {'score_mean': mean_interval([r['ours'] for r in scored]) + ('%d scored' % len(scored),),
           'zero_scores': (sum(1 for r in scored if r['ours'] == 0), None, None, ''),
           'win_rate_player': wilson_interval(wins, len(player)) + ('%d of %d' % (wins, len(player)),),
           'stalls_per_match': mean_interval([r['stalls'] or 0 for r in rows]) + ('',),
           'idle_per_match': mean_interval([r['idle_s'] or 0 for r in rows]) + ('',),
           'violations': (violations, None, None, '')}
    return out


def verdict(name, value, target, at_least):
    """'met', 'short by X' or 'no target' for one figure."""
    if target is None:
        return 'no target'
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return 'not measured'
    off = (float(target) - value) if at_least else (value - float(target))
    if off <= 1e-9:
        return 'met'
    shown = '%.0f points' % (100 * off) if name == 'win_rate_player' else '%.2f' % off
    return 'short by %s' % shown


def board_lines(robot, rows, violations, targets):
    """The robot's lines, and (met, judged) of its targets."""
    found = figures(rows, violations)
    lines = ['scoreboard %s: %d matches, seeds %s' % (
        robot, len(rows), ', '.join('%d' % r['seed'] for r in rows))]
    met = judged = 0
    for name, what, at_least in FIGURES:
        value, low, high, detail = found[name]
        target = targets.get(name)
        said = verdict(name, value, target, at_least)
        judged += target is not None
        met += said == 'met'
        percent = name == 'win_rate_player'
        scale = 100.0 if percent else 1.0
        shown = 'nan' if value is None or (isinstance(value, float) and math.isnan(value)) else (
            '%.0f%%' % (scale * value) if percent else ('%d' % value if isinstance(value, int) else '%.2f' % value))
        interval = '' if low is None else ' ci95 [%s, %s]' % tuple(
            ('%.0f%%' % (scale * v) if percent else '%.2f' % v) for v in (low, high))
        goal = '' if target is None else ' (target %s %s)' % ('>=' if at_least else '<=',
                                                             '%.0f%%' % (100 * target) if percent else target)
        lines.append('  %-20s %s%s%s%s: %s' % (what, shown, interval, ' ' + detail if detail else '', goal, said))
    return lines, met, judged


def run_matches(robot, n, seed, factor):
    """The folder of a new `make matches` run of this robot."""
    out = subprocess.run([sys.executable, os.path.join(ROOT, 'scripts', 'run_matches.py'), robot, '--n', str(n),
                          '--seed', str(seed), '--factor', str(factor)],
                         stdout=subprocess.PIPE, universal_newlines=True)
    sys.stdout.write(out.stdout)
    folders = [line.split()[1] for line in out.stdout.splitlines() if line.startswith('folder: ')]
    return folders[-1] if folders else None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--robots', default='eurobot2009,logion', help='comma-separated')
    ap.add_argument('--n', type=int, default=20)
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--factor', type=float, default=0.0)
    ap.add_argument('--judge', action='append', default=[], metavar='ROBOT=DIR',
                    help='judge a run_matches.py folder already made instead of playing')
    args = ap.parse_args()
    with open(TARGETS) as f:
        all_targets = yaml.safe_load(f) or {}
    given = dict(j.split('=', 1) for j in args.judge)
    robots = list(given) if given else [r for r in args.robots.split(',') if r]
    lines, met, judged, matches, failed = [], 0, 0, 0, False
    for robot in robots:
        folder = given.get(robot) or run_matches(robot, args.n, args.seed, args.factor)
        table = folder and os.path.join(folder, '%s_matches.txt' % robot)
        try:
            rows, violations = read_table(table)
        except (TypeError, OSError, ValueError) as e:
            lines.append('scoreboard %s: no table (%s)' % (robot, e))
            failed = True
            continue
        robot_lines, robot_met, robot_judged = board_lines(robot, rows, violations, all_targets.get(robot) or {})
        lines += robot_lines
        met, judged, matches = met + robot_met, judged + robot_judged, matches + len(rows)
    lines.append('scoreboard: robots %d matches %d targets_met %d of %d' % (len(robots), matches, met, judged))
    print('\n'.join(lines), flush=True)
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
