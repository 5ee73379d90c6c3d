"""robot_core.robot_urdf: a config's robot: block makes one URDF tree; a bad block is refused with
the parameter it names (what roslaunch shows when robot_urdf refuses a config)."""
import math
import unittest
import xml.etree.ElementTree as ET

from robot_core import robot_urdf

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


if __name__ == '__main__':
    unittest.main()
