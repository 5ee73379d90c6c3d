"""The start zone decides the colour: in a simulated match the robot's start, the HMI's side
switch, the localization's initial_pose and the opponent's start must agree with the start zone
the robot stands in (table/start_zones), or the robot plays one colour while the referee counts
the other. check_config runs these rules over the merged config; each error is one line naming
the parameter, its value and what would agree. zone_of is the one answer to "which start zone
holds this point" (the match runner's colour, the 2008 strategy's).

The side switch: a HumanInterface device's `side_switch: {input: NAME}` reads a board input that
the simulator wires to the world switch of the same name (sim/world/robot/switches/NAME); open
means the first of its `sides`, closed the second."""


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
