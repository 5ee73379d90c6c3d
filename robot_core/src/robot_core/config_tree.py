"""A robot's configuration as the launch loads it: one YAML file over another, as `rosparam load`
merges them (a dictionary updates key by key, any other value replaces). One answer for the
config checker, the URDF writer and the match runner."""
from robot_core.robot_geometry import RobotGeometry


def merged(base, over):
    """`over` merged into a copy of `base`."""
    out = dict(base)
    for key, value in over.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = merged(out[key], value)
        else:
            out[key] = value
    return out


def simulated_robot(tree):
    """sim/world/robot of a merged config with the geometry the simulator takes from the robot's
    description (/robot) where the simulated robot sets none of its own: radius, footprint, wheel_radius,
    wheel_base (/robot/track_width), the driven wheels' encoders' ticks_per_rev
    (/robot/encoder_ticks_per_rev) and each ranger's mount (the link ranger_NAME's [x, y, yaw]).
    The twin of robot_sim's parseRobot; {} when the config simulates no robot; ParameterError for
    a bad description value (RobotGeometry)."""
    world = ((tree.get('sim') or {}).get('world') or {})
    if not isinstance(world.get('robot'), dict):
        return {}
    robot = dict(world['robot'])
    described = tree.get('robot') or {}
    geometry = RobotGeometry.of_config(tree)
    for key, value in (('radius', geometry.radius), ('footprint', described.get('footprint')),
                       ('wheel_radius', geometry.wheel_radius), ('wheel_base', geometry.track_width)):
        if key not in robot and value is not None:
            robot[key] = value
    motors = robot.get('motors') or {}
    encoders = {}
    for name, e in (robot.get('encoders') or {}).items():
        e = dict(e or {})
        driven = (motors.get(e.get('motor')) or {}).get('drive')
        if driven and 'ticks_per_rev' not in e and geometry.encoder_ticks_per_rev is not None:
            e['ticks_per_rev'] = geometry.encoder_ticks_per_rev
        encoders[name] = e
    if encoders:
        robot['encoders'] = encoders
    links = described.get('links') or {}
    rangers = {}
    for name, g in (robot.get('rangers') or {}).items():
        g = dict(g or {})
        at = (links.get('ranger_' + name) or {}).get('at')
        if 'mount' not in g and isinstance(at, list) and len(at) in (3, 6):
            g['mount'] = [at[0], at[1], at[5] if len(at) == 6 else 0.0]
        rangers[name] = g
    if rangers:
        robot['rangers'] = rangers
    return robot
