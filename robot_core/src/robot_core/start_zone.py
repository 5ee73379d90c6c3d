"""The start zone decides the colour: in a simulated match the robot's start, the HMI's side
switch, the localization's initial_pose and the opponent's start must agree with the start zone
the robot stands in (table/start_zones), or the robot plays one colour while the referee counts
the other. check_config runs these rules over the merged config; each error is one line naming
the parameter, its value and what would agree. zone_of is the one answer to "which start zone
holds this point" (the match runner's colour, the 2008 strategy's).

The side switch: a HumanInterface device's `side_switch: {input: NAME}` reads a board input that
the simulator wires to the world switch of the same name (sim/world/robot/switches/NAME); open
means the first of its `sides`, closed the second.

side_overlay sets all four from one choice, the zone to play from (make run SIDE=green): the
parameters that put the simulated robot, its initial_pose, its side switch and the opponent
where that zone says."""

import math

from robot_core.geometry import wrap_angle


def zone_of(point, zones):
    """The name of the start zone [x0, y0, x1, y1] holding point [x, y, ...], or None."""
    x, y = float(point[0]), float(point[1])
    for z in zones:
        x0, y0, x1, y1 = (float(v) for v in z['rect'])
        if min(x0, x1) <= x <= max(x0, x1) and min(y0, y1) <= y <= max(y0, y1):
            return z['name']
    return None


def blocks_of_type(tree, layer, kind):
    """(name, block) of the layer's enabled blocks of this type."""
    for name, block in sorted((tree.get(layer) or {}).items()):
        if isinstance(block, dict) and block.get('type') == kind and block.get('enabled', True) is not False:
            yield name, block


def _pose(value):
    return isinstance(value, (list, tuple)) and len(value) >= 2 and all(isinstance(v, (int, float)) for v in value[:2])


def _zones_text(zones):
    return ', '.join('%s %s' % (z['name'], list(z['rect'])) for z in zones)


def errors(tree):
    """One line per disagreement with the zone the simulated robot starts in; none when the table
    has no start zones or the simulator no robot start (a config without its sim overlay)."""
    zones = [z for z in ((tree.get('table') or {}).get('start_zones') or [])
             if isinstance(z, dict) and 'name' in z and 'rect' in z]
    world = ((tree.get('sim') or {}).get('world') or {})
    robot = world.get('robot') or {}
    start = robot.get('start')
    if not zones or not _pose(start):
        return []
    ours = zone_of(start, zones)
    if ours is None:
        return ['parameter /sim/world/robot/start = %s: in no start zone; the start zones (/table/start_zones): %s'
                % (list(start), _zones_text(zones))]
    where = 'the simulated robot starts in the %s zone (/sim/world/robot/start = %s)' % (ours, list(start))
    out = []
    switches = robot.get('switches') or {}
    for name, hmi in blocks_of_type(tree, 'hal', 'HumanInterface'):
        sides, switch = hmi.get('sides'), (hmi.get('side_switch') or {}).get('input')
        if not (isinstance(sides, list) and len(sides) == 2 and switch in switches):
            continue
        closed = bool((switches[switch] or {}).get('closed', False))
        said = sides[1] if closed else sides[0]
        if said != ours:
            out.append('parameter /sim/world/robot/switches/%s/closed = %s: the side switch then says %s '
                       '(/hal/%s/sides %s: open %s, closed %s) but %s; allowed: %s'
                       % (switch, str(closed).lower(), said, name, sides, sides[0], sides[1], where,
                          str(ours == sides[1]).lower()))
    for name, loc in blocks_of_type(tree, 'hal', 'Localization'):
        pose = loc.get('initial_pose')
        zone = zone_of(pose, zones) if _pose(pose) else ours
        if zone != ours:
            out.append('parameter /hal/%s/initial_pose = %s: in %s but %s; allowed: a pose in the %s zone %s'
                       % (name, list(pose), 'the %s zone' % zone if zone else 'no start zone', where, ours,
                          [list(z['rect']) for z in zones if z['name'] == ours][0]))
    opponent = world.get('opponent') or {}
    if opponent.get('enabled', False) and _pose(opponent.get('start')):
        theirs = zone_of(opponent['start'], zones)
        others = [z for z in zones if z['name'] != ours]
        if others and theirs not in [z['name'] for z in others]:
            out.append('parameter /sim/world/opponent/start = %s: in %s but %s; allowed: a pose in the other '
                       'start zone (%s)' % (list(opponent['start']), 'the %s zone too' % theirs if theirs else
                                            'no start zone', where, _zones_text(others)))
    return out


def _mirrored(pose, length):
    """A pose mirrored across the table's middle (x = length / 2): the other side's start."""
    theta = math.pi - float(pose[2]) if len(pose) > 2 else math.pi
    return [round(length - float(pose[0]), 6), float(pose[1]), round(wrap_angle(theta), 5)]


def _place_in(zone, pose, length, width):
    """`pose` if it lies in `zone`, its mirror image if that does, else the zone's centre facing
    the table's centre."""
    zones = [zone]
    if zone_of(pose, zones):
        return [float(v) for v in pose[:3]]
    mirror = _mirrored(pose, length)
    if zone_of(mirror, zones):
        return mirror
    x0, y0, x1, y1 = (float(v) for v in zone['rect'])
    cx, cy = (x0 + x1) / 2.0, (y0 + y1) / 2.0
    return [cx, cy, round(math.atan2(width / 2.0 - cy, length / 2.0 - cx), 5)]


def side_overlay(tree, side):
    """The overlay that plays `side` (a start zone's name) in a simulated match: the simulated
    robot's start, each Localization's initial_pose, each HumanInterface's side switch and the
    opponent's start, all agreeing with the zone (errors() finds none in the merged result).
    Raises ValueError with one line when the config has no such zone or the HMI no such side."""
    table = tree.get('table') or {}
    zones = [z for z in (table.get('start_zones') or []) if isinstance(z, dict) and 'name' in z and 'rect' in z]
    names = [z['name'] for z in zones]
    if side not in names:
        raise ValueError('SIDE=%s: allowed values: %s (the start zones, /table/start_zones)'
                         % (side, ', '.join(names) if names else 'none: this config has no start zones'))
    length, width = float(table.get('length', 3.0)), float(table.get('width', 2.1))
    zone = zones[names.index(side)]
    world = ((tree.get('sim') or {}).get('world') or {})
    robot = world.get('robot') or {}
    start = _place_in(zone, robot.get('start') if _pose(robot.get('start')) else [0.25, 1.8, 0.0], length, width)
    out = {'sim': {'world': {'robot': {'start': start}}}}
    for name, hmi in blocks_of_type(tree, 'hal', 'HumanInterface'):
        sides, switch = hmi.get('sides'), (hmi.get('side_switch') or {}).get('input')
        if not switch:
            continue
        if not (isinstance(sides, list) and side in sides):
            raise ValueError('SIDE=%s: /hal/%s/sides = %s does not name it: the side switch cannot say %s'
                             % (side, name, sides, side))
        switches = out['sim']['world']['robot'].setdefault('switches', {})
        switches[switch] = {'closed': sides.index(side) == 1}
    for name, loc in blocks_of_type(tree, 'hal', 'Localization'):
        if _pose(loc.get('initial_pose')):  # else it starts lost on purpose
            out.setdefault('hal', {})[name] = {'initial_pose': list(start)}
    opponent = world.get('opponent') or {}
    others = [z for z in zones if z['name'] != side]
    if others and _pose(opponent.get('start')):
        theirs = opponent['start']
        if zone_of(theirs, others) is None:
            theirs = _place_in(others[0], theirs, length, width)
        out['sim']['world']['opponent'] = {'start': [float(v) for v in theirs[:3]]}
    return out
