#!/usr/bin/env python3
"""A robot launched in simulation (launch/<robot>.launch, the way `make run` starts it) is
alive: every expected node answers, simulated time runs, the simulator's truth and markers
flow, the URDF's every frame is in tf, the table markers come from config, and every board
(`hcl:` blocks with a type) and device (`hal:` blocks with a type) of the loaded config reports
on /diagnostics and is not STALE/ERROR. With localization and odometry configured, tf
map -> odom -> base_link exists and /mcl/pose flows. No product node (/hcl, /hal, /brain)
subscribes a topic that nothing publishes, unless config/<robot>.yaml lists it in
`optional_topics` (inputs from a person or a tool: a dead input is a wiring error otherwise).
Parameters: ~robot (eurobot2009 | logion), ~expected_nodes (list: what this robot must run)."""
import subprocess
import sys
import threading
import time
import unittest
import xml.etree.ElementTree as ET

import rospy
import rostest
import tf2_ros
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from visualization_msgs.msg import MarkerArray


def configured(section):
    """Names of the blocks of /hcl or /hal that the node loads (a dict with a type, not disabled)."""
    tree = rospy.get_param('/' + section, {})
    return sorted(k for k, v in tree.items()
                  if isinstance(v, dict) and 'type' in v and v.get('enabled', True) is not False)


class RobotTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_product_robot')
        cls.robot = rospy.get_param('~robot')
        cls.expected_nodes = rospy.get_param('~expected_nodes')
        cls.lock = threading.Lock()
        cls.diagnostics = {}
        rospy.Subscriber('/diagnostics', DiagnosticArray, cls.on_diagnostics, queue_size=100)
        cls.tf = tf2_ros.Buffer(cache_time=rospy.Duration(30))
        cls.listener = tf2_ros.TransformListener(cls.tf)
        # Simulated time runs once the simulator is up.
        rospy.wait_for_message('/clock', Clock, timeout=60.0)

    @classmethod
    def on_diagnostics(cls, msg):
        with cls.lock:
            for s in msg.status:
                cls.diagnostics[s.name] = (time.monotonic(), s)

    def test_1_expected_nodes_answer(self):
        deadline = time.monotonic() + 30.0
        missing = list(self.expected_nodes)
        while missing and time.monotonic() < deadline:
            missing = [n for n in missing if subprocess.run(['rosnode', 'ping', '-c', '1', n], stdout=subprocess.DEVNULL,
                                                            stderr=subprocess.DEVNULL).returncode != 0]
            time.sleep(1.0)
        self.assertEqual(missing, [], 'nodes not answering: %s' % missing)

    def test_2_simulated_time_and_truth_flow(self):
        t0 = rospy.get_time()
        truth = rospy.wait_for_message('/sim/ground_truth', Odometry, timeout=20.0)
        self.assertEqual(truth.header.frame_id, 'map')
        deadline = time.monotonic() + 2.0
        while time.monotonic() < deadline and rospy.get_time() - t0 <= 1.0:
            time.sleep(0.05)
        self.assertGreater(rospy.get_time() - t0, 1.0, 'simulated time does not advance')
        markers = rospy.wait_for_message('/sim/markers', MarkerArray, timeout=20.0)
        self.assertGreater(len(markers.markers), 0)

    def test_3_table_markers_from_config(self):
        msg = rospy.wait_for_message('/table_markers', MarkerArray, timeout=20.0)
        table = [m for m in msg.markers if m.ns == 'table']
        self.assertEqual(len(table), 1)
        self.assertAlmostEqual(table[0].scale.x, rospy.get_param('/table/length'))
        self.assertAlmostEqual(table[0].scale.y, rospy.get_param('/table/width'))

    def test_4_every_urdf_frame_is_in_tf(self):
        root = ET.fromstring(rospy.get_param('/robot_description'))  # as the launch wrote it from the config
        links = [l.get('name') for l in root.findall('link')]
        deadline = time.monotonic() + 20.0
        missing = links
        while missing and time.monotonic() < deadline:
            missing = [l for l in links if not self.tf.can_transform('base_link', l, rospy.Time(0))]
            time.sleep(0.5)
        self.assertEqual(missing, [], 'URDF frames not in tf: %s' % missing)

    def test_5_every_configured_board_and_device_reports(self):
        names = ['hcl/' + n for n in configured('hcl')] + ['hal/' + n for n in configured('hal')]
        sys.stdout.write('%s: %d boards and devices configured: %s\n' % (self.robot, len(names), names))
        deadline = time.monotonic() + 33.0
        problems = names
        while problems and time.monotonic() < deadline:
            now = time.monotonic()
            with self.lock:
                fresh = {n: s for n, (t, s) in self.diagnostics.items() if now - t < 3.0}
            problems = []
            for name in names:
                short = name.split('/')[1]
                mine = [s for n, s in fresh.items() if short in n]
                if not mine:
                    problems.append('%s: no fresh diagnostics' % name)
                elif any(s.level in (DiagnosticStatus.ERROR, DiagnosticStatus.STALE) for s in mine):
                    problems.append('%s: %s' % (name, '; '.join('%s [%d] %s' % (s.name, s.level, s.message) for s in mine)))
            time.sleep(1.0)
        self.assertEqual(problems, [])

    def test_6_localization_tf_chain(self):
        types = [str(rospy.get_param('/hal/%s/type' % n)) for n in configured('hal')]
        if not any('ocaliz' in t or 'Mcl' in t for t in types):
            sys.stdout.write('%s: no localization device configured: tf chain not checked\n' % self.robot)
            return
        from geometry_msgs.msg import PoseWithCovarianceStamped
        pose = rospy.wait_for_message('/mcl/pose', PoseWithCovarianceStamped, timeout=30.0)
        self.assertEqual(pose.header.frame_id, 'map')
        deadline = time.monotonic() + 20.0
        while time.monotonic() < deadline and not self.tf.can_transform('map', 'base_link', rospy.Time(0)):
            time.sleep(0.5)
        self.assertTrue(self.tf.can_transform('map', 'odom', rospy.Time(0)), 'no map -> odom')
        self.assertTrue(self.tf.can_transform('odom', 'base_link', rospy.Time(0)), 'no odom -> base_link')

    def test_7_no_product_node_waits_on_a_topic_nobody_publishes(self):
        import rosgraph
        optional = set(rospy.get_param('/optional_topics', []))
        master = rosgraph.Master('/test_product_robot')
        product = ('/hcl', '/hal', '/brain')
        time.sleep(5.0)  # every node up and subscribed
        pubs, subs, _ = master.getSystemState()
        published = {topic for topic, nodes in pubs if nodes}
        # An action server's goal and cancel inputs wait for clients by design (its status is
        # published); /rosout_agg belongs to ROS's own rosout (rostest may run without it).
        servers = {t[:-len('/status')] for t in published if t.endswith('/status')}

        def expected_silent(topic):
            return topic in optional or topic == '/rosout_agg' or (
                topic.rsplit('/', 1)[0] in servers and topic.rsplit('/', 1)[1] in ('goal', 'cancel'))
        dead = sorted('%s (subscribed by %s)' % (topic, ', '.join(n for n in nodes if n in product))
                      for topic, nodes in subs
                      if any(n in product for n in nodes) and topic not in published and not expected_silent(topic))
        self.assertEqual(dead, [], 'product nodes subscribe topics nothing publishes (list an input from a person '
                                   'or a tool in config/%s.yaml optional_topics)' % self.robot)
        unused = sorted(t for t in optional if not any(t == topic for topic, _ in subs))
        self.assertEqual(unused, [], 'optional_topics lists topics nobody subscribes')


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'product_robot', RobotTest, sys.argv)
