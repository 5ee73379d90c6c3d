#!/usr/bin/env python3
"""Camera driver against the simulator's rendered stream (top-mounted view of an empty table)."""
import subprocess
import sys
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from hcl_drivers.msg import CameraState
from sensor_msgs.msg import Image
from test_support import Recorder

TABLE_BGR = (60, 150, 60)    # robot_sim scene_renderer kTableColour
ROBOT_BGR = (200, 80, 20)    # kRobotColour


def pixel(img, u, v):
    i = v * img.step + 3 * u
    return tuple(bytearray(img.data[i:i + 3]))


def close(a, b, tol=25):
    return all(abs(x - y) <= tol for x, y in zip(a, b))


class CameraTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_camera')
        cls.image = Recorder('/hcl/camera/image', Image, queue_size=100)
        cls.state = Recorder('/hcl/camera/state', CameraState, queue_size=100)
        cls.diagnostics = Recorder('/diagnostics', DiagnosticArray, queue_size=100)
        end = time.monotonic() + 30
        while time.monotonic() < end and cls.image.last() is None:
            time.sleep(0.1)
        assert cls.image.last() is not None, 'no image'

    def test_1_frames_at_the_camera_rate_in_bgr8(self):
        t0 = time.monotonic()
        time.sleep(3.0)
        n = len(self.image.since(t0))
        self.assertAlmostEqual(n / 3.0, 10.0, delta=2.5)  # the camera's 10 fps, below the 15 Hz poll
        img = self.image.last()
        self.assertEqual((img.width, img.height, img.encoding, img.step), (320, 240, 'bgr8', 960))
        self.assertEqual(len(img.data), 960 * 240)
        self.assertEqual(img.header.frame_id, 'camera_optical_frame')
        stamps = [m.header.stamp.to_sec() for _, m in self.image.since(t0)]
        self.assertEqual(stamps, sorted(set(stamps)), 'a frame was published twice')

    def test_2_the_rendered_table_is_seen(self):
        img = self.image.last()
        self.assertTrue(close(pixel(img, 160, 120), TABLE_BGR), pixel(img, 160, 120))
        # the robot at its start (0.25, 0.25): bottom-left of the table in a top view
        s = min(320 / 3.2, 240 / 2.3)
        ox, oy = (320 - s * 3.0) / 2, (240 - s * 2.1) / 2
        robot = pixel(img, int(ox + s * 0.25), int(oy + s * (2.1 - 0.2)))
        self.assertTrue(close(robot, ROBOT_BGR, tol=40), robot)  # JPEG chroma subsampling dulls saturated colours

    def test_9_camera_gone_is_reported_and_nothing_crashes(self):
        subprocess.check_call(['rosnode', 'kill', '/sim/firmware'], stdout=subprocess.DEVNULL)
        killed = time.monotonic()
        level = None
        while time.monotonic() - killed < 5.0 and level is None:
            for _, arr in self.diagnostics.since(killed + 0.2):
                for s in arr.status:
                    if 'hcl/camera:' in s.name and s.level in (DiagnosticStatus.ERROR, DiagnosticStatus.STALE):
                        level = s
            time.sleep(0.1)
        self.assertIsNotNone(level, 'camera not reported within 5 s of its stream dying')
        out = subprocess.run(['rosnode', 'ping', '-c', '1', '/hcl'], stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        self.assertEqual(out.returncode, 0, out.stdout.decode())


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'camera', CameraTest, sys.argv)
