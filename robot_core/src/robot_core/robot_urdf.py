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
base_link (REP-105's footprint: base_link is on the floor already)."""
import math
from xml.sax.saxutils import quoteattr

# Colours every robot may use; robot/materials adds to them or changes them.
PALETTE = {
    'body': [0.6, 0.6, 0.6],
    'black': [0.05, 0.05, 0.05],
    'sensor': [0.95, 0.60, 0.10],
    'part': [0.70, 0.70, 0.70],
}
WHEEL_WIDTH = 0.02  # [m] drawn only


class GeometryError(ValueError):
    """A robot block the URDF cannot be written from: the message names the parameter."""


def _number(v, name):
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise GeometryError('parameter /robot/%s = %r: must be a number' % (name, v))
    return float(v)


def _numbers(v, sizes, name):
    if not isinstance(v, list) or len(v) not in sizes:
        raise GeometryError('parameter /robot/%s = %r: must be a list of %s numbers' % (
            name, v, ' or '.join(str(s) for s in sizes)))
    return [_number(x, '%s[%d]' % (name, i)) for i, x in enumerate(v)]


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


def _geometry(spec, name):
    if 'box' in spec:
        return '<box size="%s"/>' % ' '.join(_f(v) for v in _numbers(spec['box'], (3,), name + '/box'))
    if 'cylinder' in spec:
        r, length = _numbers(spec['cylinder'], (2,), name + '/cylinder')
        return '<cylinder radius="%s" length="%s"/>' % (_f(r), _f(length))
    if 'sphere' in spec:
        return '<sphere radius="%s"/>' % _f(_number(spec['sphere'], name + '/sphere'))
    return None


def _visual(spec, name, materials, collision=False):
    """The <visual> (and <collision>) lines of a link spec, none when it draws nothing."""
    geometry = _geometry(spec, name)
    if geometry is None:
        return []
    material = spec.get('material', 'part')
    if material not in materials:
        raise GeometryError('parameter /robot/%s/material = %r: allowed values: %s' % (
            name, material, ', '.join(sorted(materials))))
    at = _numbers(spec['visual_at'], (3, 6), name + '/visual_at') if 'visual_at' in spec else None
    lines = ['    <visual>']
    if at:
        lines.append(_origin(at, '      '))
    lines += ['      <geometry>%s</geometry>' % geometry, '      <material name=%s/>' % quoteattr(material),
              '    </visual>']
    if collision:
        lines.append('    <collision>')
        if at:
            lines.append(_origin(at, '      '))
        lines += ['      <geometry>%s</geometry>' % geometry, '    </collision>']
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


def links_of(robot):
    """[(link, parent or None, at, spec)] in URDF order: base_link, base_footprint, the body, the
    driven wheels, then robot/links."""
    out = [('base_link', None, None, dict((robot.get('links') or {}).get('base_link') or {})),
           ('base_footprint', 'base_link', [0.0, 0.0, 0.0], {})]
    if 'radius' in robot:
        radius = _number(robot['radius'], 'radius')
        height = _number(robot.get('height', 0.26), 'height')
        clearance = _number(robot.get('clearance', 0.03), 'clearance')
        out.append(('chassis_link', 'base_link', [0.0, 0.0, 0.0],
                    {'cylinder': [radius, height], 'visual_at': [0.0, 0.0, clearance + height / 2.0],
                     'material': 'body', 'collision': True}))
    if 'wheel_radius' in robot and 'track_width' in robot:
        wheel = _number(robot['wheel_radius'], 'wheel_radius')
        half = _number(robot['track_width'], 'track_width') / 2.0
        width = _number(robot.get('wheel_width', WHEEL_WIDTH), 'wheel_width')
        for side, y in (('left', half), ('right', -half)):
            out.append(('%s_wheel_link' % side, 'base_link', [0.0, y, wheel],
                        {'cylinder': [wheel, width], 'visual_at': [0.0, 0.0, 0.0, math.pi / 2, 0.0, 0.0],
                         'material': 'black'}))
    links = robot.get('links') or {}
    if not isinstance(links, dict):
        raise GeometryError('parameter /robot/links: must be a dictionary of links')
    for name, spec in links.items():
        if name == 'base_link':
            continue
        if not isinstance(spec, dict):
            raise GeometryError('parameter /robot/links/%s = %r: must be a dictionary' % (name, spec))
        at = _numbers(spec.get('at', [0.0, 0.0, 0.0]), (3, 6), 'links/%s/at' % name)
        out.append((name, str(spec.get('parent', 'base_link')), at, spec))
    return out


def urdf(robot):
    """The URDF (a string) of a config's `robot:` block; GeometryError for a bad block."""
    if not isinstance(robot, dict) or not robot.get('name'):
        raise GeometryError('parameter /robot/name: missing (the robot block needs at least its name)')
    materials = dict(PALETTE)
    for name, rgb in (robot.get('materials') or {}).items():
        materials[name] = _numbers(rgb, (3,), 'materials/%s' % name)
    links = links_of(robot)
    names = [n for n, _, _, _ in links]
    for name, parent, _, _ in links:
        if parent is not None and parent not in names:
            raise GeometryError('parameter /robot/links/%s/parent = %r: no such link (links: %s)' % (
                name, parent, ', '.join(names)))
        if names.count(name) > 1:
            raise GeometryError('parameter /robot/links/%s: a link the block already makes' % name)
    lines = ['<?xml version="1.0"?>',
             '<!-- Written by robot_description/scripts/robot_urdf from the robot: block of the robot\'s',
             '     config (config/ROBOT.yaml): edit the config, not this. REP-103 axes, REP-105 frames. -->',
             '<robot name=%s>' % quoteattr(str(robot['name']))]
    for name in sorted(materials):
        lines.append('  <material name=%s><color rgba="%s 1"/></material>' % (
            quoteattr(name), ' '.join(_f(c) for c in materials[name])))
    for name, parent, at, spec in links:
        lines += _link(name, _visual(spec, 'links/' + name, materials, collision=spec.get('collision', False)))
        if parent is not None:
            lines += _joint(name, parent, at)
    lines.append('</robot>')
    return '\n'.join(lines) + '\n'
