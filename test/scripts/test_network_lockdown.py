#!/usr/bin/env python3
"""Nobody outside the robot drives it, in network namespaces of this machine, one "Wi-Fi":
  netns "robot"   (NET.1 on a bridge): the master and the skeleton robot (emulator, HCL, HAL,
                  brain, network guard), bound to its address (ROS_IP), behind the firewall
                  make install-robot installs (robot_tools.install.host_files firewall_rules, loaded
                  with nft as the installer does)
  netns "laptop"  (NET.2): the team's laptop, on the config's allow-list
  netns "foreign" (NET.3): somebody else's laptop in the pits
With the firewall: the foreign laptop cannot reach the master, a node's XML-RPC port or a
service, and the drops are counted; the allowed laptop subscribes to the robot's topics (rviz).
With the firewall off: the foreign node is reported on /diagnostics (network guard, command
gates), and during a match (HAL's /effectors/match_end in the future) its lamp commands and its
/effectors/deactivate call are ignored; outside a match they are obeyed. Needs root."""
import json
import os
import subprocess
import sys
import tempfile
import time
import unittest

import rospy
import rostest
import yaml

import netns_pair  # beside this script

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
from robot_tools.install import host_files, plan  # the installer's own rules

PID = os.getpid()
NET = '10.214.%d' % (PID % 250)
ROBOT_IP, LAPTOP_IP, FOREIGN_IP = NET + '.1', NET + '.2', NET + '.3'
NS = {'robot': 'lock_robot_%d' % PID, 'laptop': 'lock_laptop_%d' % PID, 'foreign': 'lock_foreign_%d' % PID}
PORT = 11612
MASTER = 'http://%s:%d' % (ROBOT_IP, PORT)
ADDRESS = {'robot': ROBOT_IP, 'laptop': LAPTOP_IP, 'foreign': FOREIGN_IP}
TABLE = 'robot_skeleton'


def env_for(who):
    env = dict(os.environ)
    env.pop('ROS_HOSTNAME', None)
    env.update(ROS_IP=ADDRESS[who], ROS_MASTER_URI=MASTER, ROS_HOME=tempfile.gettempdir() + '/lock_ros_%d' % PID)
    return env


def run(who, cmd, timeout=30, check=False):
    """A command in `who`'s namespace, as a node there would run: (exit code, stdout+stderr)."""
    try:
        out = subprocess.run(['ip', 'netns', 'exec', NS[who]] + cmd, env=env_for(who), stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, universal_newlines=True, timeout=timeout)
    except subprocess.TimeoutExpired as e:
        return 124, (e.stdout or '') if isinstance(e.stdout, str) else ''
    if check and out.returncode != 0:
        raise AssertionError('%s in %s: exit %d: %s' % (' '.join(cmd), who, out.returncode, out.stdout[-2000:]))
    return out.returncode, out.stdout


def python(who, code, timeout=30):
    return run(who, [sys.executable, '-c', code], timeout=timeout)


def can_connect(who, host, port):
    rc, _ = python(who, 'import socket; socket.create_connection((%r, %d), timeout=2).close()' % (host, port), timeout=10)
    return rc == 0


DIAGNOSTICS = '''
import json, time, rospy
from diagnostic_msgs.msg import DiagnosticArray
rospy.init_node('lockdown_observer', anonymous=True, disable_signals=True)
seen = {}
def cb(m):
    for s in m.status:
        seen[s.name] = {'level': ord(s.level) if isinstance(s.level, bytes) else s.level, 'message': s.message,
                        'hardware_id': s.hardware_id, 'values': {k.key: k.value for k in s.values}}
rospy.Subscriber('/diagnostics', DiagnosticArray, cb, queue_size=100)
time.sleep(%f)
print(json.dumps(seen))
'''


class LockdownTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_network_lockdown', anonymous=True)  # rostest's master: nothing else
        cls.tmp = tempfile.mkdtemp(prefix='lockdown_')
        cls.procs = []
        netns_pair.delete(NS.values())
        for ns in NS.values():
            netns_pair.ip('netns', 'add', ns)
            netns_pair.ip('-n', ns, 'link', 'set', 'lo', 'up')
        r = NS['robot']
        netns_pair.ip('-n', r, 'link', 'add', 'wifi', 'type', 'bridge')
        netns_pair.ip('-n', r, 'addr', 'add', ROBOT_IP + '/24', 'dev', 'wifi')
        netns_pair.ip('-n', r, 'link', 'set', 'wifi', 'up')
        for who in ('laptop', 'foreign'):
            here, there = 'l%s%d' % (who[0], PID % 100000), 'r%s%d' % (who[0], PID % 100000)
            netns_pair.ip('link', 'add', here, 'type', 'veth', 'peer', 'name', there)
            netns_pair.ip('link', 'set', here, 'netns', NS[who])
            netns_pair.ip('link', 'set', there, 'netns', r)
            netns_pair.ip('-n', r, 'link', 'set', there, 'master', 'wifi')
            netns_pair.ip('-n', r, 'link', 'set', there, 'up')
            netns_pair.ip('-n', NS[who], 'addr', 'add', ADDRESS[who] + '/24', 'dev', here)
            netns_pair.ip('-n', NS[who], 'link', 'set', here, 'up')
        # The robot's config: its address, the team's laptop allowed (an overlay on skeleton.yaml).
        cls.network = {'address': ROBOT_IP, 'master_port': PORT, 'robot_hosts': [], 'allow': [LAPTOP_IP]}
        cls.overlay = os.path.join(cls.tmp, 'network.yaml')
        with open(cls.overlay, 'w') as f:
            yaml.safe_dump({'computer': {'network': cls.network}}, f)
        cls.firewall(True)
        cls.start('robot', ['roscore', '-p', str(PORT)])
        deadline = time.time() + 60
        while not can_connect('robot', ROBOT_IP, PORT):
            assert time.time() < deadline, 'no master in the robot namespace'
            time.sleep(0.5)
        cls.start('robot', ['roslaunch', '--wait', os.path.join(ROOT, 'launch', 'skeleton.launch'),
                            'overlay:=' + cls.overlay])
        rc, out = run('robot', ['rostopic', 'echo', '-n', '1', '/hal/example_device/reading'], timeout=90)
        assert rc == 0, 'the skeleton robot did not come up in its namespace: ' + out[-1500:]

    @classmethod
    def start(cls, who, cmd):
        log = open(os.path.join(cls.tmp, '%s_%d.log' % (who, len(cls.procs))), 'w')
        cls.procs.append(subprocess.Popen(['ip', 'netns', 'exec', NS[who]] + cmd, env=env_for(who), stdout=log,
                                          stderr=subprocess.STDOUT, start_new_session=True))

    @classmethod
    def firewall(cls, on):
        if on:
            rules = os.path.join(cls.tmp, 'robot.nft')
            with open(rules, 'w') as f:
                f.write(host_files.firewall_rules('skeleton', cls.network, plan.read_port_range()))
            run('robot', ['nft', '-f', rules], check=True)
        else:
            run('robot', ['nft', 'delete', 'table', 'inet', TABLE], check=True)

    @classmethod
    def tearDownClass(cls):
        for p in reversed(cls.procs):
            netns_pair.stop(p)
        netns_pair.delete(NS.values())

    def lookup(self, kind, name):
        rc, out = python('robot', 'import rosgraph; print(rosgraph.Master("/t").%s(%r))' % (kind, name))
        self.assertEqual(rc, 0, out)
        uri = out.strip().splitlines()[-1]
        host_port = uri.split('://', 1)[1].split('/', 1)[0]
        return host_port.split(':')[0], int(host_port.split(':')[1])

    def diagnostics(self, seconds):
        rc, out = python('robot', DIAGNOSTICS % seconds, timeout=seconds + 30)
        self.assertEqual(rc, 0, out)
        return json.loads(out.strip().splitlines()[-1])

    def dropped(self):
        rc, out = run('robot', ['nft', '-j', 'list', 'counter', 'inet', TABLE, 'ros_dropped'], check=True)
        for item in json.loads(out)['nftables']:
            if 'counter' in item:
                return item['counter']['packets']
        self.fail('no ros_dropped counter: ' + out)

    def test_1_foreign_laptop_is_kept_out(self):
        before = self.dropped()
        hal = self.lookup('lookupNode', '/hal')
        service = self.lookup('lookupService', '/brain/switch_strategy')
        self.assertEqual(hal[0], ROBOT_IP, 'the robot\'s nodes must advertise its address')
        for target in ((ROBOT_IP, PORT), hal, service):
            self.assertTrue(can_connect('laptop', *target), 'the allowed laptop must reach %s:%d' % target)
            self.assertFalse(can_connect('foreign', *target), 'the foreign laptop reached %s:%d' % target)
        rc, out = run('foreign', ['rostopic', 'pub', '-1', '/cmd_vel', 'geometry_msgs/Twist', '{linear: {x: 0.5}}'],
                      timeout=6)
        self.assertNotEqual(rc, 0, 'a foreign laptop published cmd_vel: ' + out)
        self.assertGreater(self.dropped(), before, 'the drops must be counted')

    def test_2_allowed_laptop_sees_the_robot(self):
        rc, out = run('laptop', ['rostopic', 'echo', '-n', '1', '/hcl/example_board/state'], timeout=60)
        self.assertEqual(rc, 0, out)
        self.assertIn('dial', out)
        diag = self.diagnostics(3.0)
        self.assertIn('network guard', diag)
        self.assertEqual(diag['network guard']['level'], 0, diag['network guard'])

    def test_3_foreign_node_reported_and_ignored_during_a_match(self):
        self.firewall(False)
        try:
            # A match runs: HAL's latched match end, a minute from now.
            self.start('robot', ['rostopic', 'pub', '-l', '/effectors/match_end', 'std_msgs/Time',
                                 '{data: {secs: %d, nsecs: 0}}' % (time.time() + 3600)])
            time.sleep(3.0)
            self.start('foreign', ['rostopic', 'pub', '-r', '20', '__name:=intruder', '/hal/example_device/lamp',
                                   'std_msgs/Float64', '{data: 0.9}'])
            rc, out = run('foreign', ['rosservice', 'call', '/effectors/deactivate'], timeout=60)
            self.assertEqual(rc, 0, out)
            self.assertIn('success: False', out)
            self.assertIn('refused', out)
            rc, out = run('robot', ['rostopic', 'echo', '-n', '1', '/effectors/deactivated'], timeout=20)
            self.assertIn('data: False', out, 'a foreign caller deactivated the effectors during the match')
            rc, out = run('foreign', ['rosservice', 'call', '/brain/switch_strategy', 'example'], timeout=60)
            self.assertIn('success: False', out)
            diag = self.diagnostics(4.0)
            guard = diag['network guard']
            self.assertEqual(guard['level'], 2)
            said = guard['values'].get('foreign /intruder')
            self.assertIsNotNone(said, 'the network guard did not report the foreign publisher: %s' % guard)
            self.assertIn(FOREIGN_IP, said)
            self.assertIn('/hal/example_device/lamp', said)
            self.assertFalse([n for n in diag if n.startswith('network guard: ')], 'one item per node (goes STALE)')
            gate = diag.get('command gate /hal: /intruder')
            self.assertIsNotNone(gate, 'HAL did not report the foreign lamp commands: %s' % list(diag))
            self.assertEqual(gate['level'], 2)
            self.assertGreater(int(gate['values']['ignored']), 10)
            self.assertEqual(int(gate['values']['obeyed']), 0)
            # After the match (no match armed): the foreign commands are obeyed, still reported.
            self.start('robot', ['rostopic', 'pub', '-l', '/effectors/match_end', 'std_msgs/Time',
                                 '{data: {secs: 0, nsecs: 0}}'])
            time.sleep(3.0)
            rc, out = run('foreign', ['rosservice', 'call', '/effectors/deactivate'], timeout=60)
            self.assertIn('success: True', out)
            diag = self.diagnostics(3.0)
            self.assertGreater(int(diag['command gate /hal: /intruder']['values']['obeyed']), 0)
        finally:
            self.firewall(True)


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'test_network_lockdown', LockdownTest)
