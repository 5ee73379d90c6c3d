"""The robot's URDF, written from its config's `robot:` block: the geometry has one source.

    robot:
      name: logion
      radius: 0.17           # [m] the body: a cylinder of this radius (chassis_link, also its
      height: 0.26           #     collision), this high, `clearance` above the floor
      clearance: 0.03
      wheel_radius: 0.03     # the driven wheels (left_wheel_link, right_wheel_link), track_width
      track_width: 0.28      # apart, wheel_width wide (default 0.02)
      materials: {body: [0.8, 0.2, 0.2]}    # rgb, over the palette below
      links:                 # every other link, in order
        ranger_front: {at: [0.17, 0, 0.10, 0, 0, 0], box: [0.02, 0.04, 0.015], material: sensor}
        camera_optical_frame: {parent: camera_link, at: [0, 0, 0, -1.5708, 0, -1.5708]}

A link of `links`: `parent` (default base_link), `at` [x, y, z] or [x, y, z, roll, pitch, yaw]
from the parent (REP-103), and what rviz draws, if anything: `box` [x, y, z], `cylinder`
[radius, length], `sphere` radius, at `visual_at` in the link, in `material`. A `base_link`
entry draws base_link itself (the skeleton's box). Joints are fixed (nothing publishes
/joint_states), named after the link without its _link/_frame ending. base_footprint sits on
base_link (REP-105's footprint: base_link is on the floor already).

Every key is read through robot_core.params (radius, wheel_radius, track_width through
RobotGeometry, as the devices read them): a bad value is one ParameterError line naming it
(`parameter /robot/links/lamp/at[1] = 'up': must be a number`), and what the reader declared is the
robot table of the parameter tables (`robot_urdf CONFIG --describe`)."""
import collections
import math
from xml.sax.saxutils import quoteattr

from robot_core.params import REQUIRED, ParameterError, Params
from robot_core.robot_geometry import RobotGeometry

# Colours every robot may use; robot/materials adds to them or changes them.
PALETTE = {
    'body': [0.6, 0.6, 0.6],
    'black': [0.05, 0.05, 0.05],
    'sensor': [0.95, 0.60, 0.10],
    'part': [0.70, 0.70, 0.70],
}
WHEEL_WIDTH = 0.02  # [m] drawn only
AT = '[x, y, z] or [x, y, z, roll, pitch, yaw]'

# What a bad robot block raises: callers and tests that catch GeometryError catch ParameterError.
GeometryError = ParameterError

# What rviz draws of a link: its <geometry> (None: nothing), where in the link, in which material.
Drawing = collections.namedtuple('Drawing', 'geometry visual_at material collision')
NOTHING = Drawing(None, None, 'part', False)


def _checked(name, values, sizes, positive=False, within=None):
    """`values` as floats when it is a list of `sizes` finite numbers (each > 0 where `positive`,
    in [lo, hi] for `within`); else ParameterError naming `name`, or `name[i]` for one element."""
    if not isinstance(values, list) or len(values) not in sizes:
        raise ParameterError('parameter %s = %r: must be a list of %s numbers' % (
            name, values, ' or '.join(str(s) for s in sizes)))
    out = []
    for i, x in enumerate(values):
        if isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x):
            raise ParameterError('parameter %s[%d] = %r: must be a number' % (name, i, x))
        if positive and not x > 0:
            raise ParameterError('parameter %s[%d] = %r: must be > 0' % (name, i, x))
        if within and not within[0] <= x <= within[1]:
            raise ParameterError('parameter %s[%d] = %r: must be in %s .. %s' % (name, i, x, within[0], within[1]))
        out.append(float(x))
    return out


def _numbers(params, key, sizes, default, rule, meaning, positive=False):
    """The list `key` of `sizes` numbers (_checked), or `default` when absent."""
    values = params.value(key, default, list, rule=rule, meaning=meaning)
    return None if values is None else _checked(params.qualified(key), values, sizes, positive)


def _number(params, key, default, rule, meaning, ok):
    """A finite number that `ok` accepts, the rule the table writes `rule`."""
    return params.value(key, default, float, rule=rule, meaning=meaning,
                        check=lambda v: '' if math.isfinite(v) and ok(v) else 'must be a number ' + rule)


def _f(x):
    """A number as URDF files write it: short, no trailing zeros, no -0."""
    text = ('%.6f' % x).rstrip('0').rstrip('.')
    return '0' if text in ('-0', '') else text


def _origin(values, indent):
    xyz, rpy = values[:3], (values[3:] if len(values) == 6 else [0.0, 0.0, 0.0])
    attrs = ' xyz="%s"' % ' '.join(_f(v) for v in xyz)
    if any(rpy):
        attrs += ' rpy="%s"' % ' '.join(_f(v) for v in rpy)
    return '%s<origin%s/>' % (indent, attrs)


def _box(size):
    return '<box size="%s"/>' % ' '.join(_f(v) for v in size)


def _cylinder(radius, length):
    return '<cylinder radius="%s" length="%s"/>' % (_f(radius), _f(length))


def _sphere(radius):
    return '<sphere radius="%s"/>' % _f(radius)


def _drawing(link, materials):
    """What a link of robot/links draws: its box, else its cylinder, else its sphere, if any."""
    box = _numbers(link, 'box', (3,), None, '[x, y, z], each > 0', '[m] draws a box of this size', positive=True)
    cylinder = _numbers(link, 'cylinder', (2,), None, '[radius, length], each > 0',
                        "[m] draws a cylinder along the link's z (when it has no box)", positive=True)
    sphere = _number(link, 'sphere', None, '> 0', '[m] draws a sphere of this radius (when it has no box, no cylinder)',
                     lambda v: v > 0)
    visual_at = _numbers(link, 'visual_at', (3, 6), None, AT,
                         "[m, rad] where the drawing sits in the link (default: at the link's origin)")
    material = link.value('material', 'part', str, rule='a name of the palette or of robot/materials',
                          check=lambda m: '' if m in materials else 'allowed values: ' + ', '.join(sorted(materials)),
                          meaning="the drawing's colour: body, black, sensor, part or a name of robot/materials")
    collision = link.value('collision', False, bool, meaning="true: the drawing is the link's collision shape too")
    geometry = _box(box) if box else _cylinder(*cylinder) if cylinder else _sphere(sphere) if sphere else None
    return Drawing(geometry, visual_at, material, collision)


def _visual(drawing):
    """The <visual> (and <collision>) lines of a link, none when it draws nothing."""
    if drawing.geometry is None:
        return []
    at = drawing.visual_at
    lines = ['    <visual>']
    if at:
        lines.append(_origin(at, '      '))
    lines += ['      <geometry>%s</geometry>' % drawing.geometry,
              '      <material name=%s/>' % quoteattr(drawing.material), '    </visual>']
    if drawing.collision:
        lines.append('    <collision>')
        if at:
            lines.append(_origin(at, '      '))
        lines += ['      <geometry>%s</geometry>' % drawing.geometry, '    </collision>']
    return lines


def _link(name, lines):
    if not lines:
        return ['  <link name=%s/>' % quoteattr(name)]
    return ['  <link name=%s>' % quoteattr(name)] + lines + ['  </link>']


def _joint(child, parent, at):
    stem = child
    for ending in ('_link', '_frame'):
        if stem.endswith(ending):
            stem = stem[:-len(ending)]
    return ['  <joint name=%s type="fixed">' % quoteattr(stem + '_joint'),
            '    <parent link=%s/><child link=%s/>' % (quoteattr(parent), quoteattr(child)),
            _origin(at, '    '), '  </joint>']


def _materials(robot):
    """{name: rgb} of the palette with robot/materials over it."""
    given = robot.value('materials', {}, dict, rule='name: [r, g, b], each 0 .. 1',
                        meaning='colours by name [r, g, b] over the palette (body, black, sensor, part)')
    materials = dict(PALETTE)
    for name, rgb in given.items():
        materials[name] = _checked(robot.qualified('materials/%s' % name), rgb, (3,), within=(0.0, 1.0))
    return materials


def links_of(robot, materials):
    """[(link, parent or None, at, Drawing)] in URDF order of the Params of a robot block: base_link,
    base_footprint, the body, the driven wheels, then robot/links."""
    geometry = RobotGeometry.read(robot)
    height = _number(robot, 'height', 0.26, '> 0', "[m] the body's height (the chassis cylinder, drawn with radius)",
                     lambda v: v > 0)
    clearance = _number(robot, 'clearance', 0.03, '>= 0', "[m] the body's underside above the floor", lambda v: v >= 0)
    width = _number(robot, 'wheel_width', WHEEL_WIDTH, '> 0', "[m] the driven wheels' width (drawn only)",
                    lambda v: v > 0)
    names = robot.block_names('links')
    block = robot.block('links')
    robot.describe('links', 'every link but the body and the driven wheels, by name, in order '
                            '(base_link: what base_link itself draws)')
    base = _drawing(block.block('base_link'), materials) if 'base_link' in names else NOTHING
    out = [('base_link', None, None, base), ('base_footprint', 'base_link', [0.0, 0.0, 0.0], NOTHING)]
    if geometry.radius is not None:
        out.append(('chassis_link', 'base_link', [0.0, 0.0, 0.0],
                    Drawing(_cylinder(geometry.radius, height), [0.0, 0.0, clearance + height / 2.0], 'body', True)))
    if geometry.wheel_radius is not None and geometry.track_width is not None:
        wheel, half = geometry.wheel_radius, geometry.track_width / 2.0
        for side, y in (('left', half), ('right', -half)):
            out.append(('%s_wheel_link' % side, 'base_link', [0.0, y, wheel],
                        Drawing(_cylinder(wheel, width), [0.0, 0.0, 0.0, math.pi / 2, 0.0, 0.0], 'black', False)))
    for name in names:
        if name == 'base_link':
            continue
        link = block.block(name)
        parent = link.value('parent', 'base_link', str,
                            meaning='the link it hangs on: base_link or a link of robot/links')
        at = _numbers(link, 'at', (3, 6), [0.0, 0.0, 0.0], AT, "[m, rad] its origin in its parent's (REP-103)")
        out.append((name, parent, at, _drawing(link, materials)))
    return out


def urdf(robot):
    """The URDF (a string) of a config's `robot:` block (a dictionary, or its Params named /robot);
    ParameterError for a bad block."""
    robot = robot if isinstance(robot, Params) else Params(robot, '/robot')
    name = robot.value('name', REQUIRED, str, check=lambda v: '' if v else 'must not be empty',
                       meaning="the robot's name: the URDF's robot name, which match_panel shows")
    materials = _materials(robot)
    links = links_of(robot, materials)
    names = [n for n, _, _, _ in links]
    for link, parent, _, _ in links:
        if parent is not None and parent not in names:
            raise ParameterError('parameter %s = %r: no such link (links: %s)' % (
                robot.qualified('links/%s/parent' % link), parent, ', '.join(names)))
        if names.count(link) > 1:
            raise ParameterError('parameter %s: a link the block already makes' % robot.qualified('links/' + link))
    lines = ['<?xml version="1.0"?>',
             '<!-- Written by robot_description/scripts/robot_urdf from the robot: block of the robot\'s',
             '     config (config/ROBOT.yaml): edit the config, not this. REP-103 axes, REP-105 frames. -->',
             '<robot name=%s>' % quoteattr(name)]
    for material in sorted(materials):
        lines.append('  <material name=%s><color rgba="%s 1"/></material>' % (
            quoteattr(material), ' '.join(_f(c) for c in materials[material])))
    for link, parent, at, drawing in links:
        lines += _link(link, _visual(drawing))
        if parent is not None:
            lines += _joint(link, parent, at)
    lines.append('</robot>')
    return '\n'.join(lines) + '\n'
