#!/usr/bin/env python3
"""rviz starts headless (Xvfb) with the shipped eurobot2009 config and shows the scene: the
table from config, the robot model where tf puts it, and the particle cloud in its colour
(magenta) where the cloud is. The test plays localization's part: it publishes the tf
map -> base_link and a particle cloud, and compares screenshots without and with the cloud."""
import math
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import unittest

import rospkg
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import Pose, PoseArray, TransformStamped
from PIL import Image

CLOUD_AT = (2.0, 1.3)      # [m] in map
ROBOT_AT = (1.0, 0.5)
TABLE = (3.0, 2.1)         # config/eurobot2009.yaml table


def classify(img):
    """The table's box on screen (the big green area: rows and columns with many green pixels,
    so toolbar icons do not count) and, inside it, the magenta (particles) and blue (robot body)
    pixels; plus the number of distinct colours of the whole screen (blank-screen check)."""
    px = img.convert('RGB').load()
    w, h = img.size
    green, magenta, blue = [], [], []
    colours = set()
    for y in range(0, h, 2):
        for x in range(0, w, 2):
            r, g, b = px[x, y]
            colours.add((r >> 3, g >> 3, b >> 3))
            if g > r + 40 and g > b + 40 and g > 70:
                green.append((x, y))
            elif r > 150 and b > 150 and g < 90 and abs(r - b) < 70:
                magenta.append((x, y))
            elif b > r + 60 and b > g + 60:
                blue.append((x, y))
    rows, cols = {}, {}
    for x, y in green:
        rows[y] = rows.get(y, 0) + 1
        cols[x] = cols.get(x, 0) + 1
    rows = [y for y, n in rows.items() if n >= 40]
    cols = [x for x, n in cols.items() if n >= 40]
    table = (min(cols), min(rows), max(cols), max(rows)) if rows and cols else None

    def inside(points):
        if table is None:
            return []
        return [(x, y) for x, y in points if table[0] - 5 <= x <= table[2] + 5 and table[1] - 5 <= y <= table[3] + 5]
    return {'table': table, 'magenta': inside(magenta), 'blue': inside(blue)}, len(colours)


def box(points):
    xs, ys = [p[0] for p in points], [p[1] for p in points]
    return min(xs), min(ys), max(xs), max(ys)


def free_display():
    for n in range(150 + os.getpid() % 50, 260):
        if not os.path.exists('/tmp/.X%d-lock' % n) and not os.path.exists('/tmp/.X11-unix/X%d' % n):
            return n
    raise RuntimeError('no free X display number')


class RvizTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_product_rviz')
        cls.tmp = tempfile.mkdtemp(prefix='product_rviz_')
        cls.display = free_display()
        cls.auth = os.path.join(cls.tmp, 'Xauthority')
        config = os.path.join(rospkg.RosPack().get_path('robot_description'), 'rviz', 'eurobot2009.rviz')
        cls.rviz = subprocess.Popen(
            ['xvfb-run', '-n', str(cls.display), '-f', cls.auth, '-s', '-screen 0 1024x768x24',
             'rviz', '-d', config], stdout=open(os.path.join(cls.tmp, 'rviz.log'), 'w'),
            stderr=subprocess.STDOUT, start_new_session=True)
        cls.stop = threading.Event()
        cls.robot_on = threading.Event()
        cls.cloud_on = threading.Event()
        cls.thread = threading.Thread(target=cls.publish)
        cls.thread.start()

    @classmethod
    def tearDownClass(cls):
        cls.stop.set()
        cls.thread.join()
        try:
            os.killpg(cls.rviz.pid, signal.SIGTERM)
            cls.rviz.wait(timeout=10)
        except (ProcessLookupError, subprocess.TimeoutExpired):
            os.killpg(cls.rviz.pid, signal.SIGKILL)
        shutil.rmtree(cls.tmp, ignore_errors=True)

    @classmethod
    def publish(cls):
        tf = tf2_ros.TransformBroadcaster()
        cloud = rospy.Publisher('/mcl/particlecloud', PoseArray, queue_size=1)
        rnd = random.Random(3)
        poses = []
        for _ in range(400):
            p = Pose()
            p.position.x = CLOUD_AT[0] + rnd.gauss(0, 0.08)
            p.position.y = CLOUD_AT[1] + rnd.gauss(0, 0.08)
            a = rnd.uniform(-math.pi, math.pi)
            p.orientation.z, p.orientation.w = math.sin(a / 2), math.cos(a / 2)
            poses.append(p)
        while not cls.stop.is_set() and not rospy.is_shutdown():
            if not cls.robot_on.is_set():
                time.sleep(0.1)
                continue
            t = TransformStamped()
            t.header.stamp = rospy.Time.now()
            t.header.frame_id, t.child_frame_id = 'map', 'base_link'
            t.transform.translation.x, t.transform.translation.y = ROBOT_AT
            t.transform.rotation.w = 1.0
            tf.sendTransform(t)
            if cls.cloud_on.is_set():
                m = PoseArray()
                m.header.stamp, m.header.frame_id = rospy.Time.now(), 'map'
                m.poses = poses
                cloud.publish(m)
            time.sleep(0.1)

    def shot(self, name):
        path = os.path.join(self.tmp, name)
        env = dict(os.environ, DISPLAY=':%d' % self.display, XAUTHORITY=self.auth)
        subprocess.run(['import', '-window', 'root', path], env=env, check=True, timeout=30,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        return classify(Image.open(path))

    def wait_for(self, name, condition, timeout):
        deadline = time.monotonic() + timeout
        found, ncolours = {}, 0
        while time.monotonic() < deadline:
            if self.rviz.poll() is not None:
                self.fail('rviz exited with %s: %s' % (self.rviz.returncode, open(os.path.join(self.tmp, 'rviz.log')).read()[-2000:]))
            try:
                found, ncolours = self.shot(name)
                if condition(found):
                    return found, ncolours
            except subprocess.CalledProcessError:
                pass  # X server not up yet
            time.sleep(1.0)
        return found, ncolours

    def test_scene_then_particle_cloud(self):
        # Without a cloud: the table and the robot, and no magenta anywhere.
        found, ncolours = self.wait_for('empty.png', lambda f: f['table'], 60.0)
        self.assertGreater(ncolours, 20, 'the screenshot is (nearly) blank')
        self.assertTrue(found.get('table'), 'no table on screen')
        x0, y0, x1, y1 = found['table']
        # The table is drawn with the config's proportions (3.0 x 2.1 m, top view, square pixels).
        self.assertGreater(x1 - x0, 300)
        self.assertAlmostEqual((x1 - x0) / float(y1 - y0), TABLE[0] / TABLE[1], delta=0.08)
        self.assertLess(len(found['magenta']), 5, 'magenta on the table before any particle was published')
        # No tf yet, so no robot: what is blue now belongs to the table (start zones).
        table_blue = set(found['blue'])

        # With tf map -> base_link, the robot model appears where tf puts it (y up on screen).
        self.robot_on.set()
        found, _ = self.wait_for('robot.png', lambda f: len(set(f['blue']) - table_blue) > 30, 30.0)
        robot = list(set(found['blue']) - table_blue)
        self.assertGreater(len(robot), 30, 'no robot model on the table')
        self.assertLess(len(found['magenta']), 5, 'magenta on the table before any particle was published')
        bx0, by0, bx1, by1 = box(robot)
        fx = ((bx0 + bx1) / 2 - x0) / float(x1 - x0)
        fy = (y1 - (by0 + by1) / 2) / float(y1 - y0)
        self.assertAlmostEqual(fx, ROBOT_AT[0] / TABLE[0], delta=0.06, msg='robot x on screen')
        self.assertAlmostEqual(fy, ROBOT_AT[1] / TABLE[1], delta=0.08, msg='robot y on screen')

        self.cloud_on.set()
        found, _ = self.wait_for('after.png', lambda f: f['table'] and len(f['magenta']) > 200, 30.0)
        self.assertGreater(len(found['magenta']), 200, 'the particle cloud is not drawn')
        mx0, my0, mx1, my1 = box(found['magenta'])
        fx = ((mx0 + mx1) / 2 - x0) / float(x1 - x0)
        fy = (y1 - (my0 + my1) / 2) / float(y1 - y0)
        self.assertAlmostEqual(fx, CLOUD_AT[0] / TABLE[0], delta=0.06, msg='cloud x on screen')
        self.assertAlmostEqual(fy, CLOUD_AT[1] / TABLE[1], delta=0.08, msg='cloud y on screen')

        # A long "not ready" line in the Match panel wraps: the dock does not widen and push the
        # 3D view aside; the view keeps at least half the window.
        from smart_brain.msg import MatchStatus
        status = rospy.Publisher('/brain/match_status', MatchStatus, queue_size=1, latch=True)
        long_line = 'not ready: ' + '; '.join('/Devices/device_%d: device is WARN: refreshing at 13.5 Hz, configured '
                                              '20.0 Hz' % i for i in range(12))
        status.publish(MatchStatus(state='waiting_for_start', ready=False, readiness=long_line, strategy='match'))
        time.sleep(3.0)  # the panel renders at 5 Hz
        found, _ = self.wait_for('long_status.png', lambda f: f['table'], 20.0)
        self.assertTrue(found.get('table'), 'no table on screen after the long status')
        lx0, _, lx1, _ = found['table']
        width = Image.open(os.path.join(self.tmp, 'long_status.png')).size[0]
        self.assertGreater(lx1 - lx0, 0.9 * (x1 - x0), 'the 3D view shrank: the table %d px wide, was %d'
                           % (lx1 - lx0, x1 - x0))
        self.assertLess(lx0, width / 2, 'the 3D view starts at %d px of %d: less than half the window' % (lx0, width))


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'product_rviz', RvizTest, sys.argv)
