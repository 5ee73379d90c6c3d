"""robot_core.robot_urdf: a config's robot: block makes one URDF tree; a bad block is refused with
the parameter it names (what roslaunch shows when robot_urdf refuses a config)."""
import math
import os
import subprocess
import sys
import tempfile
import unittest
import xml.etree.ElementTree as ET

import yaml
from robot_core import robot_urdf
from robot_core.params import ParameterError, Params
from robot_core.robot_geometry import MEANINGS

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'robot_description', 'scripts',
                      'robot_urdf')

ROBOT = {
    'name': 'tiny', 'radius': 0.15, 'height': 0.2, 'clearance': 0.02, 'wheel_radius': 0.03, 'track_width': 0.24,
    'materials': {'body': [0.1, 0.2, 0.3]},
    'links': {
        'ranger_front': {'at': [0.15, 0, 0.1], 'box': [0.02, 0.04, 0.015], 'material': 'sensor'},
        'camera_link': {'at': [0.1, 0, 0.3, 0, 0.5, 0], 'box': [0.03, 0.08, 0.03]},
        'camera_optical_frame': {'parent': 'camera_link', 'at': [0, 0, 0, -1.5708, 0, -1.5708]},
    },
}


def tree(robot):
    root = ET.fromstring(robot_urdf.urdf(robot))
    joints = {j.find('child').get('link'): j for j in root.findall('joint')}
    return root, joints


class RobotUrdfTest(unittest.TestCase):
    def test_body_wheels_and_links_from_the_block(self):
        root, joints = tree(ROBOT)
        links = [l.get('name') for l in root.findall('link')]
        self.assertEqual(links, ['base_link', 'base_footprint', 'chassis_link', 'left_wheel_link', 'right_wheel_link',
                                 'ranger_front', 'camera_link', 'camera_optical_frame'])
        self.assertEqual([l for l in links if l not in joints], ['base_link'])  # one tree
        chassis = root.find("link[@name='chassis_link']")
        self.assertEqual(chassis.find('visual/geometry/cylinder').get('radius'), '0.15')
        self.assertEqual(chassis.find('visual/origin').get('xyz'), '0 0 0.12')  # clearance + height / 2
        self.assertIsNotNone(chassis.find('collision'))
        self.assertEqual(joints['left_wheel_link'].find('origin').get('xyz'), '0 0.12 0.03')
        self.assertEqual(joints['right_wheel_link'].find('origin').get('xyz'), '0 -0.12 0.03')
        optical = joints['camera_optical_frame']
        self.assertEqual(optical.get('name'), 'camera_optical_joint')
        self.assertEqual(optical.find('parent').get('link'), 'camera_link')
        self.assertEqual(optical.find('origin').get('rpy'), '-1.5708 0 -1.5708')
        body = root.find("material[@name='body']/color").get('rgba')
        self.assertEqual(body, '0.1 0.2 0.3 1')
        roll = float(root.find("link[@name='left_wheel_link']/visual/origin").get('rpy').split()[0])
        self.assertAlmostEqual(roll, math.pi / 2, places=5)

    def test_a_bad_block_names_the_parameter(self):
        def refused(change, text):
            robot = dict(ROBOT, links=dict(ROBOT['links']))
            change(robot)
            with self.assertRaises(robot_urdf.GeometryError) as caught:
                robot_urdf.urdf(robot)
            self.assertIn(text, str(caught.exception))
        refused(lambda r: r.pop('name'), '/robot/name')
        refused(lambda r: r['links'].update(lamp={'parent': 'mast_link'}), "/robot/links/lamp/parent = 'mast_link'")
        refused(lambda r: r['links'].update(lamp={'sphere': 0.03, 'material': 'gold'}),
                "/robot/links/lamp/material = 'gold'")
        refused(lambda r: r['links'].update(lamp={'box': [0.1, 0.1]}), '/robot/links/lamp/box')
        refused(lambda r: r['links'].update(lamp={'at': [0, 'up', 0]}), '/robot/links/lamp/at[1]')
        refused(lambda r: r.update(radius='wide'), "/robot/radius = 'wide'")
        refused(lambda r: r['links'].update(chassis_link={}), '/robot/links/chassis_link')

    def test_a_bad_value_is_one_parameter_error_naming_it(self):
        def refused(change, message):
            robot = dict(ROBOT, links=dict(ROBOT['links']))
            change(robot)
            with self.assertRaises(ParameterError) as caught:
                robot_urdf.urdf(robot)
            self.assertEqual(str(caught.exception), message)
        refused(lambda r: r.update(track_width=0), 'parameter /robot/track_width = 0: must be > 0')
        refused(lambda r: r.update(height=-0.2), 'parameter /robot/height = -0.2: must be a number > 0')
        refused(lambda r: r.update(wheel_width='thin'), "parameter /robot/wheel_width = 'thin': must be a number")
        refused(lambda r: r.update(materials={'body': [0.1, 2, 0.3]}), 'parameter /robot/materials/body[1] = 2: '
                'must be in 0.0 .. 1.0')
        refused(lambda r: r['links'].update(lamp={'sphere': -0.03}), 'parameter /robot/links/lamp/sphere = -0.03: '
                'must be a number > 0')
        refused(lambda r: r['links'].update(lamp=[0, 0, 1]), 'parameter /robot/links/lamp = [0, 0, 1]: '
                'must be a dictionary')
        refused(lambda r: r['links'].update(lamp={'collision': 'yes'}), "parameter /robot/links/lamp/collision = "
                "'yes': must be a boolean")

    def test_every_key_of_the_block_is_declared_with_a_meaning(self):
        robot = Params(ROBOT, '/robot')
        robot_urdf.urdf(robot)
        self.assertEqual(robot.unasked(), [])
        declared = robot.declarations()
        self.assertEqual(declared['radius'].meaning, MEANINGS['radius'])  # RobotGeometry's, the C++ reader's
        self.assertEqual(declared['links'].type, 'dictionary of named blocks')
        self.assertEqual(declared['links/<name>/at'].rule, '[x, y, z] or [x, y, z, roll, pitch, yaw]')
        self.assertFalse([name for name in declared if 'ranger_front' in name])  # named <name>, not by the config
        self.assertEqual([name for name, d in declared.items() if not d.meaning], [])

    def test_describe_prints_the_declarations_as_table_rows(self):
        with tempfile.NamedTemporaryFile('w', suffix='.yaml') as f:
            yaml.safe_dump({'robot': ROBOT}, f)
            f.flush()
            done = subprocess.run([sys.executable, SCRIPT, f.name, '--describe'], stdout=subprocess.PIPE,
                                  stderr=subprocess.PIPE, universal_newlines=True)
        self.assertEqual(done.returncode, 0, done.stderr)
        rows = [line.split('\t') for line in done.stdout.splitlines()]
        self.assertTrue(rows)
        self.assertEqual({len(row) for row in rows}, {7})
        self.assertEqual({row[0] for row in rows}, {'robot'})
        self.assertIn(['robot', 'radius', 'number', 'required', '', '> 0', MEANINGS['radius']], rows)
        self.assertIn('links/<name>/parent', [row[1] for row in rows])
        self.assertEqual([row[1] for row in rows if not row[6]], [])

    def test_the_script_refuses_a_bad_block_in_one_line(self):
        with tempfile.NamedTemporaryFile('w', suffix='.yaml') as f:
            yaml.safe_dump({'robot': dict(ROBOT, radius=-1)}, f)
            f.flush()
            done = subprocess.run([sys.executable, SCRIPT, f.name], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                  universal_newlines=True)
        self.assertEqual(done.returncode, 1)
        self.assertEqual(done.stdout, '')
        self.assertEqual(done.stderr, 'robot_urdf: %s: parameter /robot/radius = -1: must be > 0\n' % f.name)


if __name__ == '__main__':
    unittest.main()
