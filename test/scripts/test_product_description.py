#!/usr/bin/env python3
"""The robot descriptions: every URDF (robot_description/scripts/robot_urdf writes it from the
config's robot: block, as the launch does) is one tree under base_link with the frames the
devices and rviz rely on, and config/<robot>.yaml names only frames that exist in its URDF (a
ranger's frame_id is a link; a simulated ranger's mount is where the URDF puts it); a bad robot
block is refused with one line.
Also: table_markers draws the config's table and refuses a bad one with one clear line."""
import glob
import math
import os
import subprocess
import sys
import unittest
import xml.etree.ElementTree as ET

import rospkg
import rospy
from robot_core.geometry import wrap_angle
import rostest
import yaml
from robot_core.config_tree import merged, simulated_robot
from visualization_msgs.msg import MarkerArray

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
ROBOT_URDF = os.path.join(rospkg.RosPack().get_path('robot_description'), 'scripts', 'robot_urdf')
COMMON = ['base_link', 'base_footprint', 'left_wheel_link', 'right_wheel_link', 'caster_link',
          'compass_link', 'beacon_receiver_link', 'camera_link', 'camera_optical_frame']
# Frames beyond those of a robot on the table (COMMON) that rviz and the robot's devices rely on.
EXTRA_FRAMES = {
    'eurobot2009': ['hand_link', 'hand_lift_link', 'hand_left_finger_link', 'hand_right_finger_link',
                    'left_free_wheel_link', 'right_free_wheel_link'],
    'logion': ['harvester_link', 'harvester_door_link'],
    'skeleton': ['lamp_link'],
}
GLOBAL_FRAMES = {'map', 'odom'}
FRAME_KEYS = ('frame_id', 'frame', 'sensor_frame', 'camera_frame', 'receiver_frame', 'base_frame')


def robots():
    """Every robot here: a launch/ROBOT.launch with its config/ROBOT.yaml (a new robot is checked too)."""
    names = [os.path.basename(p)[:-len('.launch')] for p in glob.glob(os.path.join(ROOT, 'launch', '*.launch'))]
    return sorted(n for n in names if os.path.exists(os.path.join(ROOT, 'config', n + '.yaml')))


def table_robots():
    """The robots that play on the table: their simulator has a driven robot (sim/world/robot)."""
    return [r for r in robots() if 'motors' in sim_robot(r)]


def nested_has(tree, path):
    """Whether the dictionaries `tree` hold a value at the key path `path`."""
    for key in path:
        if not isinstance(tree, dict) or key not in tree:
            return False
        tree = tree[key]
    return True


def sim_robot(robot):
    """The simulated robot as the simulator reads it: sim/world/robot with the geometry it takes
    from the robot's description (robot_core.config_tree.simulated_robot)."""
    cfg, sim = load_config(robot, True)
    return simulated_robot(merged(cfg, sim))


def expected_frames(robot):
    common = COMMON if robot in table_robots() else ['base_link']
    return common + EXTRA_FRAMES.get(robot, [])


def urdf_root(robot):
    """The robot's URDF as the launch sets /robot_description, parsed."""
    out = subprocess.run([ROBOT_URDF, os.path.join(ROOT, 'config', robot + '.yaml')], stdout=subprocess.PIPE,
                         universal_newlines=True, check=True).stdout
    return ET.fromstring(out)


def parse(robot):
    """(links, {child: (parent, xyz, rpy)})."""
    root = urdf_root(robot)
    links = [l.get('name') for l in root.findall('link')]
    joints = {}
    for j in root.findall('joint'):
        o = j.find('origin')
        xyz = [float(v) for v in (o.get('xyz', '0 0 0') if o is not None else '0 0 0').split()]
        rpy = [float(v) for v in (o.get('rpy', '0 0 0') if o is not None else '0 0 0').split()]
        joints[j.find('child').get('link')] = (j.find('parent').get('link'), xyz, rpy)
    return links, joints


def frames_named_in(node, path=''):
    """(path, frame) for every frame-naming key anywhere in a config tree."""
    out = []
    if isinstance(node, dict):
        for k, v in node.items():
            p = path + '/' + str(k)
            if k in FRAME_KEYS and isinstance(v, str):
                out.append((p, v))
            else:
                out.extend(frames_named_in(v, p))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            out.extend(frames_named_in(v, '%s[%d]' % (path, i)))
    return out


def load_config(robot, sim):
    with open(os.path.join(ROOT, 'config', robot + '.yaml')) as f:
        cfg = yaml.safe_load(f) or {}
    if sim:
        with open(os.path.join(ROOT, 'config', robot + '.sim.yaml')) as f:
            return cfg, (yaml.safe_load(f) or {})
    return cfg, {}


class DescriptionTest(unittest.TestCase):
    def test_urdf_is_one_tree_with_expected_frames(self):
        self.assertGreaterEqual(len(robots()), 3)
        for robot in robots():
            expected = expected_frames(robot)
            links, joints = parse(robot)
            self.assertEqual(len(links), len(set(links)), '%s: duplicate link names' % robot)
            roots = [l for l in links if l not in joints]
            self.assertEqual(roots, ['base_link'], '%s: the tree must have base_link as its only root' % robot)
            for child, (parent, _, _) in joints.items():
                self.assertIn(parent, links, '%s: joint to %s from unknown %s' % (robot, child, parent))
            for frame in expected:
                self.assertIn(frame, links, '%s: frame %s missing' % (robot, frame))
            if robot in table_robots():
                rangers = [l for l in links if l.startswith('ranger_')]
                self.assertGreaterEqual(len(rangers), 4, '%s: rangers %s' % (robot, rangers))

    def test_config_frames_exist_in_urdf(self):
        for robot in robots():
            links, _ = parse(robot)
            cfg, sim = load_config(robot, True)
            for path, frame in frames_named_in(cfg) + frames_named_in(sim):
                self.assertIn(frame, set(links) | GLOBAL_FRAMES,
                              'config/%s: %s = %s is not a link of its URDF (robot/links)' % (robot, path, frame))

    def test_simulated_ranger_mounts_match_urdf(self):
        # sim/world/robot/rangers/<name>/mount: [x, y, theta] in base_link; the URDF link is
        # <name> or ranger_<name>. A ranger the simulator has must be in the URDF, same place.
        checked = 0
        for robot in table_robots():
            links, joints = parse(robot)
            rangers = sim_robot(robot).get('rangers') or {}
            for name, r in rangers.items():
                link = name if name in links else 'ranger_' + name
                self.assertIn(link, links, 'config/%s.sim.yaml sim/world/robot/rangers/%s: the robot has no such '
                              'ranger (no URDF link %s; the HAL rangers are %s): rename it and take its mount '
                              'from the URDF' % (robot, name, link, sorted(l for l in links if l.startswith('ranger_'))))
                mount = r.get('mount') if isinstance(r, dict) else None
                if not isinstance(mount, list) or len(mount) < 2:
                    continue
                parent, xyz, rpy = joints[link]
                self.assertEqual(parent, 'base_link')
                self.assertAlmostEqual(xyz[0], mount[0], delta=0.01, msg='%s %s x' % (robot, link))
                self.assertAlmostEqual(xyz[1], mount[1], delta=0.01, msg='%s %s y' % (robot, link))
                if len(mount) >= 3:
                    d = wrap_angle(rpy[2] - mount[2])
                    self.assertLess(abs(d), 0.02, '%s %s yaw %.3f vs mount %.3f' % (robot, link, rpy[2], mount[2]))
                checked += 1
        sys.stdout.write('simulated ranger mounts checked against the URDF: %d\n' % checked)

    def test_simulated_geometry_matches_urdf(self):
        # Wheels (radius, track) and the collision outline of sim/world/robot match the URDF.
        checked = 0
        for robot in table_robots():
            _, joints = parse(robot)
            world_robot = sim_robot(robot)
            root = urdf_root(robot)
            _, left, _ = joints['left_wheel_link']
            _, right, _ = joints['right_wheel_link']
            self.assertAlmostEqual(left[1] - right[1], world_robot['wheel_base'], delta=0.002, msg=robot + ' track')
            self.assertAlmostEqual(left[2], world_robot['wheel_radius'], delta=0.002, msg=robot + ' wheel radius')
            chassis = [l for l in root.findall('link') if l.get('name') == 'chassis_link'][0]
            radius = float(chassis.find('visual/geometry/cylinder').get('radius'))
            self.assertAlmostEqual(radius, world_robot['radius'], delta=0.005, msg=robot + ' outline radius')
            checked += 1
        sys.stdout.write('simulated robot geometries checked against the URDF: %d\n' % checked)

    def test_robot_geometry_has_one_source(self):
        # config/<robot>.yaml robot: the URDF, the simulated robot and every block of the config
        # that uses a radius, a track or the encoder scale agree with it.
        checked = 0
        for robot in table_robots():
            cfg, sim = load_config(robot, True)
            # The shipped simulated robot is the robot as described: no copy of the geometry in
            # the sim overlay (a copy is for a simulator that differs on purpose: calibration).
            own = sim['sim']['world']['robot']
            copies = ['sim/world/robot/' + k for k in ('radius', 'wheel_radius', 'wheel_base') if k in own]
            copies += ['sim/world/robot/rangers/%s/mount' % n for n, r in (own.get('rangers') or {}).items()
                       if 'mount' in (r or {})]
            copies += ['sim/world/robot/encoders/%s/ticks_per_rev' % n for n, e in (own.get('encoders') or {}).items()
                       if e.get('motor') in ('left', 'right') and 'ticks_per_rev' in e]
            self.assertEqual(copies, [], 'config/%s.sim.yaml copies the robot\'s geometry (config/%s.yaml robot:): '
                             'remove them, the simulator reads the description' % (robot, robot))
            geometry = cfg['robot']
            hal = cfg['hal']
            links, joints = parse(robot)
            root = urdf_root(robot)
            chassis = [l for l in root.findall('link') if l.get('name') == 'chassis_link'][0]
            _, left, _ = joints['left_wheel_link']
            _, right, _ = joints['right_wheel_link']
            world_robot = sim_robot(robot)
            radius, track, wheel = geometry['radius'], geometry['track_width'], geometry['wheel_radius']
            for where, value in (('urdf chassis_link', float(chassis.find('visual/geometry/cylinder').get('radius'))),
                                 ('sim/world/robot/radius', world_robot['radius'])):
                self.assertAlmostEqual(value, radius, delta=1e-6, msg='%s: %s vs robot/radius' % (robot, where))
            for where, value in (('urdf wheel joints', left[1] - right[1]),
                                 ('sim/world/robot/wheel_base', world_robot['wheel_base'])):
                self.assertAlmostEqual(value, track, delta=1e-6, msg='%s: %s vs robot/track_width' % (robot, where))
            # The HAL's blocks take the radius and the track from the description (RobotGeometry): a
            # copy in a shipped block would stop following it (a calibrated track, a new robot).
            hal_copies = [where for where in ('localization/robot_radius', 'driver/avoidance/robot_radius',
                                              'driver/limits/track_width', 'drive/track_width',
                                              'odometry/pairs/driven/track_width')
                          if nested_has(hal, where.split('/'))]
            self.assertEqual(hal_copies, [], 'config/%s.yaml hal: copies the robot\'s geometry: remove them, '
                             'the devices read robot: (robot_core/robot_geometry.h)' % robot)
            for where, value in (('urdf wheel joint height', left[2]),
                                 ('sim/world/robot/wheel_radius', world_robot['wheel_radius'])):
                self.assertAlmostEqual(value, wheel, delta=1e-6, msg='%s: %s vs robot/wheel_radius' % (robot, where))
            ticks = geometry['encoder_ticks_per_rev']
            for name, enc in world_robot['encoders'].items():
                if enc.get('motor') in ('left', 'right'):
                    self.assertEqual(enc['ticks_per_rev'], ticks, '%s: sim encoder %s' % (robot, name))
            per_metre = ticks / (2 * math.pi * wheel)
            driven = hal['odometry']['pairs']['driven']
            for side in ('left', 'right'):
                self.assertAlmostEqual(driven[side + '_ticks_per_meter'] / per_metre, 1.0, delta=1e-4,
                                       msg='%s: odometry %s_ticks_per_meter' % (robot, side))
            # The localization's rangers sit where the URDF puts their links.
            for name, r in hal['localization'].get('rangers', {}).items():
                link = name if name in links else 'ranger_' + name
                self.assertIn(link, links, '%s: hal/localization/rangers/%s has no URDF link' % (robot, name))
                parent, xyz, rpy = joints[link]
                self.assertEqual(parent, 'base_link')
                self.assertAlmostEqual(r['x'], xyz[0], delta=1e-3, msg='%s %s x' % (robot, name))
                self.assertAlmostEqual(r['y'], xyz[1], delta=1e-3, msg='%s %s y' % (robot, name))
                d = wrap_angle(rpy[2] - r['yaw'])
                self.assertLess(abs(d), 1e-3, '%s %s yaw %.4f vs %.4f' % (robot, name, r['yaw'], rpy[2]))
                checked += 1
        sys.stdout.write('localization ranger mounts checked against the URDF: %d\n' % checked)
        self.assertGreater(checked, 0)

    def test_table_markers_draw_the_config_table(self):
        rospy.init_node('test_product_description', anonymous=True)
        msg = rospy.wait_for_message('/table_markers', MarkerArray, timeout=20.0)
        table = [m for m in msg.markers if m.ns == 'table']
        self.assertEqual(len(table), 1)
        length, width = rospy.get_param('/table/length'), rospy.get_param('/table/width')
        self.assertAlmostEqual(table[0].scale.x, length)
        self.assertAlmostEqual(table[0].scale.y, width)
        self.assertEqual(table[0].header.frame_id, 'map')
        self.assertAlmostEqual(table[0].pose.position.x, length / 2)
        # Its top is just below z = 0, so flat things drawn at z = 0 stay visible.
        self.assertLess(table[0].pose.position.z + table[0].scale.z / 2, 0.0)
        beacons = sorted((m.id, m.pose.position.x, m.pose.position.y) for m in msg.markers if m.ns == 'beacons')
        expected = rospy.get_param('/table/beacons')
        self.assertEqual(len(beacons), len(expected))
        for (_, x, y), (ex, ey) in zip(beacons, expected):
            self.assertAlmostEqual(x, ex)
            self.assertAlmostEqual(y, ey)
        self.assertEqual(len([m for m in msg.markers if m.ns == 'borders']), 4)

    def test_table_markers_refuse_a_bad_table(self):
        # Its own private table param, on the test's master: one line naming the parameter.
        rospy.set_param('/bad_table', {'length': -1.0, 'width': 2.1})
        out = subprocess.run(['rosrun', 'robot_description', 'table_markers', '_table:=/bad_table',
                              '__name:=bad_table_markers'], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             timeout=30)
        text = out.stdout.decode()
        self.assertNotEqual(out.returncode, 0, text)
        self.assertIn('/bad_table/length', text)
        self.assertIn('must be a number > 0', text)


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'product_description', DescriptionTest, sys.argv)
