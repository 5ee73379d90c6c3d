"""A match's configuration: the robot's config as the launch loads it (config/ROBOT.yaml with its
sim overlay), the opponents a series cycles through, and the overlays a runner writes beside each
match (the opponent, a tuning trial's parameters, the user's overlay files, the side played)."""
import math
import os
import sys

import yaml
from robot_core import start_zone
from robot_core.config_tree import merged  # the config as roslaunch loads one rosparam file after another

from robot_tools.paths import ROOT

OPPONENTS = ('random_walk', 'route', 'blocker', 'player')
ROUTE_CLEARANCE = 0.30  # [m] between the game elements' centres and the route
BLOCKER_PAUSE = 1.0e6  # [s] at the goal: longer than any match, so the blocker never leaves


def robot_config(robot):
    """config/ROBOT.yaml with config/ROBOT.sim.yaml over it (the simulated robot's parameters)."""
    config = {}
    for name in (robot + '.yaml', robot + '.sim.yaml'):
        path = os.path.join(ROOT, 'config', name)
        if os.path.exists(path):
            with open(path) as f:
                config = merged(config, yaml.safe_load(f) or {})
    return config


def zone_centre(zone):
    x0, y0, x1, y1 = zone['rect']
    return [(x0 + x1) / 2.0, (y0 + y1) / 2.0]


def our_colour(config):
    """The start zone our robot starts in (the referee's rule for our colour), else `red`."""
    start = config['sim']['world']['robot'].get('start', [0.25, 1.8, 0.0])
    return start_zone.zone_of(start, config['table'].get('start_zones', [])) or 'red'


def our_goal(config):
    """Centre of the first score zone that scores for us: team `placer` or our colour."""
    colour = our_colour(config)
    for zone in config['table'].get('score_zones', []):
        if zone.get('team') in ('placer', colour):
            return zone_centre(zone)
    raise SystemExit('matches: no table/score_zones zone with team placer or %s in the config' % colour)


def route_around_elements(config):
    """A loop around the game elements (their bounding box grown by ROUTE_CLEARANCE), kept off
    the borders and out of the start zones (where a waiting robot would stop the route),
    starting at the corner nearest the opponent's start and going round."""
    table, opponent = config['table'], config['sim']['world']['opponent']
    length, width = table['length'], table['width']
    radius = opponent.get('radius', 0.16)
    points = [e['at'] for e in table.get('elements', [])] or [[length / 4, width / 4], [3 * length / 4, 3 * width / 4]]
    x0 = min(p[0] for p in points) - ROUTE_CLEARANCE
    x1 = max(p[0] for p in points) + ROUTE_CLEARANCE
    y0 = min(p[1] for p in points) - ROUTE_CLEARANCE
    y1 = max(p[1] for p in points) + ROUTE_CLEARANCE
    keep_off = radius + 0.05
    for zone in table.get('start_zones', []):
        zx0, zy0, zx1, zy1 = zone['rect']
        if zx1 + keep_off < x0 or zx0 - keep_off > x1:
            continue  # beside the loop
        if (zy0 + zy1) / 2 > (y0 + y1) / 2:
            y1 = min(y1, zy0 - keep_off)
        else:
            y0 = max(y0, zy1 + keep_off)
    x0, x1 = max(x0, keep_off), min(x1, length - keep_off)
    y0, y1 = max(y0, keep_off), min(y1, width - keep_off)
    loop = [[x1, y1], [x1, y0], [x0, y0], [x0, y1]]
    start = opponent.get('start', [length, width])
    first = min(range(4), key=lambda i: math.hypot(loop[i][0] - start[0], loop[i][1] - start[1]))
    return [[round(v, 3) for v in p] for p in loop[first:] + loop[:first]]


def opponent_params(kind, config):
    """The sim/world/opponent parameters of one opponent kind."""
    if kind == 'random_walk':
        return {'mode': 'random_walk'}
    if kind == 'route':
        return {'mode': 'script', 'waypoints': route_around_elements(config)}
    if kind == 'blocker':
        return {'mode': 'script', 'waypoints': [[round(v, 3) for v in our_goal(config)]], 'pause': BLOCKER_PAUSE}
    if kind == 'player':
        return {'mode': 'player'}
    raise ValueError(kind)


def match_overlay(opponent, params=None):
    """A match's parameters over the config: `params` (a tuning trial's, or none) and its opponent."""
    return merged(params or {}, {'sim': {'world': {'opponent': opponent}}})


def user_overlay(paths, who):
    """The parameters of a user's overlay files (OVERLAY=a.yaml or OVERLAY="a.yaml b.yaml", here
    comma-separated, each over the one before), {} for none; a clear exit when one is unreadable."""
    out = {}
    for path in [p for p in (paths or '').split(',') if p]:
        try:
            with open(path) as f:
                data = yaml.safe_load(f) or {}
        except (OSError, yaml.YAMLError) as e:
            sys.exit('%s: --overlay %s: %s' % (who, path, e))
        if not isinstance(data, dict):
            sys.exit('%s: --overlay %s: must be a YAML dictionary of parameters (as config/<robot>.yaml)' % (who, path))
        out = merged(out, data)
    return out


def side_overlay(robot, user, side, who):
    """The overlay that plays `side` (a start zone) over the config and the user's overlay
    (robot_core.start_zone.side_overlay); a clear exit when the config has no such zone."""
    try:
        return start_zone.side_overlay(merged(robot_config(robot), user), side)
    except ValueError as e:
        sys.exit('%s: %s' % (who, e))


def side_overlay_file(robot, overlay_paths, side, folder, who):
    """side_overlay written to FOLDER/side.yaml, for a launch's overlay argument: its path."""
    path = os.path.join(folder, 'side.yaml')
    with open(path, 'w') as f:
        f.write('# scripts/run_matches.py: the parameters that play from the %s start zone\n' % side)
        yaml.safe_dump(side_overlay(robot, user_overlay(overlay_paths, who), side, who), f, default_flow_style=None)
    return path


def with_duration(overlay, seconds):
    """`overlay` with the match shortened to `seconds` (brain/match/duration, which the simulated
    referee follows too): a quick check of a runner's machinery, not of the robot. None: as is."""
    return merged(overlay, {'brain': {'match': {'duration': seconds}}}) if seconds else overlay


def write_overlay(folder, overlay):
    """FOLDER/overlay.yaml, the launch argument overlay: loaded after the robot's config."""
    path = os.path.join(folder, 'overlay.yaml')
    with open(path, 'w') as f:
        f.write('# scripts/run_matches.py: this match\'s opponent and parameters (launch argument overlay)\n')
        yaml.safe_dump(overlay, f, default_flow_style=None)
    return path
