#!/usr/bin/env python3
"""Distributed deployment between two network namespaces of this machine, one ROS master:
  netns "robot"   (10.x.y.1/30): the master, the skeleton's board emulator and HCL
  netns "station" (10.x.y.2/30): HAL and the brain
joined by a veth pair and nothing else (no other address exists in either namespace).
~mode selects how the halves are started, the two ways docs/real-robot.md "Distributed deployment" gives:
  split: one launch per computer: skeleton.launch run_hal_brain:=false in "robot",
         skeleton.launch run_hcl:=false in "station";
  ssh:   ONE launch in "station" with hcl_machine:=<robot address>: roslaunch's <machine> tag
         starts the HCL half over ssh on the robot (an sshd of this test listens in "robot" only).
Topics must flow both ways across the link: board state up to HAL in the other namespace,
the brain's lamp command down to the emulated firmware. Needs root (ip netns)."""
import os
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

import rospy
import rostest

import netns_pair  # beside this script

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
PID = os.getpid()
NET = '10.213.%d' % (PID % 250)            # our own /30, inside our own namespaces only
ROBOT_IP, STATION_IP = NET + '.1', NET + '.2'
NS_ROBOT, NS_STATION = 'prod_robot_%d' % PID, 'prod_station_%d' % PID
VETH = ('pvr%d' % (PID % 100000), 'pvs%d' % (PID % 100000))
PORT = 11611
MASTER = 'http://%s:%d' % (ROBOT_IP, PORT)


def env_for(address):
    env = dict(os.environ)
    env.pop('ROS_HOSTNAME', None)
    env.update(ROS_IP=address, ROS_MASTER_URI=MASTER)
    return env


class DistributedTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_product_distributed', anonymous=True)  # on rostest's master: for ~mode only
        cls.mode = rospy.get_param('~mode', 'split')
        assert cls.mode in ('split', 'ssh'), '~mode must be split or ssh'
        cls.tmp = tempfile.mkdtemp(prefix='product_netns_')
        cls.procs = []
        netns_pair.create((NS_ROBOT, NS_STATION), VETH, (ROBOT_IP, STATION_IP))
        cls.start('roscore', NS_ROBOT, ROBOT_IP, ['roscore', '-p', str(PORT)])
        launch = os.path.join(ROOT, 'launch', 'skeleton.launch')
        if cls.mode == 'split':
            cls.start('robot', NS_ROBOT, ROBOT_IP, ['roslaunch', '--wait', launch, 'run_hal_brain:=false'])
            cls.start('station', NS_STATION, STATION_IP, ['roslaunch', '--wait', launch, 'run_hcl:=false'])
        else:
            home, loader = cls.ssh_setup()
            cls.start('station', NS_STATION, STATION_IP,
                      ['roslaunch', '--wait', launch, 'hcl_machine:=' + ROBOT_IP, 'env_loader:=' + loader],
                      extra_env={'HOME': home})

    @classmethod
    def ssh_setup(cls):
        """An sshd in the robot namespace only, a key pair for root, known_hosts and the env-loader
        the robot runs the HCL half with (workspace of this test, ROS_IP of the robot)."""
        d = cls.tmp
        subprocess.run(['ssh-keygen', '-q', '-t', 'ed25519', '-N', '', '-f', d + '/host_key'], check=True)
        home = d + '/home'
        os.makedirs(home + '/.ssh', mode=0o700)
        subprocess.run(['ssh-keygen', '-q', '-t', 'ed25519', '-N', '', '-f', home + '/.ssh/id_ed25519'], check=True)
        shutil.copy(home + '/.ssh/id_ed25519.pub', d + '/authorized_keys')
        with open(d + '/host_key.pub') as f:
            host = f.read().split()
        with open(home + '/.ssh/known_hosts', 'w') as f:
            f.write('%s %s %s\n' % (ROBOT_IP, host[0], host[1]))
        with open(d + '/sshd_config', 'w') as f:
            f.write('ListenAddress %s\nPort 22\nHostKey %s/host_key\nAuthorizedKeysFile %s/authorized_keys\n'
                    'PidFile %s/sshd.pid\nStrictModes no\nUsePAM no\nPasswordAuthentication no\n'
                    'PermitRootLogin prohibit-password\n' % (ROBOT_IP, d, d, d))
        os.makedirs('/run/sshd', exist_ok=True)  # sshd's privilege separation directory
        cls.start('sshd', NS_ROBOT, ROBOT_IP, ['/usr/sbin/sshd', '-D', '-e', '-f', d + '/sshd_config'])
        devel = os.environ['CMAKE_PREFIX_PATH'].split(':')[0]
        loader = d + '/env_loader.sh'
        with open(loader, 'w') as f:
            f.write('#!/bin/sh\n# what a robot computer\'s env-loader does: workspace + its own address\n'
                    'export PATH=/usr/bin:/bin:$PATH ROS_IP=%s ROS_MASTER_URI=%s\n'
                    '. %s/setup.sh\nexec "$@"\n' % (ROBOT_IP, MASTER, devel))
        os.chmod(loader, 0o755)
        deadline = time.monotonic() + 10.0
        while not os.path.exists(d + '/sshd.pid') and time.monotonic() < deadline:
            time.sleep(0.2)
        return home, loader

    @classmethod
    def start(cls, name, ns, address, cmd, extra_env=None):
        log = open(os.path.join(cls.tmp, name + '.log'), 'w')
        env = env_for(address)
        env.update(extra_env or {})
        p = subprocess.Popen(['ip', 'netns', 'exec', ns] + cmd, env=env, stdout=log,
                             stderr=subprocess.STDOUT, start_new_session=True)
        cls.procs.append((name, p))

    @classmethod
    def tearDownClass(cls):
        for _, p in reversed(cls.procs):
            netns_pair.stop(p)
        netns_pair.delete((NS_ROBOT, NS_STATION))
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def run_in(self, ns, address, cmd, timeout=30):
        out = subprocess.run(['ip', 'netns', 'exec', ns] + cmd, env=env_for(address), stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, timeout=timeout)
        return out.returncode, out.stdout.decode()

    def logs(self):
        text = ''
        for name, _ in self.procs:
            with open(os.path.join(self.tmp, name + '.log')) as f:
                text += '\n--- %s ---\n%s' % (name, f.read()[-1500:])
        return text

    def wait_nodes(self, nodes, timeout=60.0):
        deadline = time.monotonic() + timeout
        listed = ''
        while time.monotonic() < deadline:
            rc, listed = self.run_in(NS_STATION, STATION_IP, ['rosnode', 'list'])
            if rc == 0 and all(n in listed.split() for n in nodes):
                return listed
            time.sleep(1.0)
        self.fail('nodes %s not all up; rosnode list: %s%s' % (nodes, listed, self.logs()))

    def test_1_namespaces_only_see_each_other(self):
        for ns in (NS_ROBOT, NS_STATION):
            rc, routes = self.run_in(ns, ROBOT_IP, ['ip', '-4', 'route'])
            self.assertEqual(rc, 0)
            self.assertEqual([l.split()[0] for l in routes.strip().splitlines()], [NET + '.0/30'], routes)

    def test_2_each_half_runs_in_its_namespace(self):
        self.wait_nodes(['/sim/firmware', '/hcl', '/hal', '/brain', '/robot_state_publisher'])
        for node, address in (('/hcl', ROBOT_IP), ('/sim/firmware', ROBOT_IP), ('/hal', STATION_IP),
                              ('/brain', STATION_IP)):
            rc, info = self.run_in(NS_STATION, STATION_IP, ['rosnode', 'info', node])
            self.assertEqual(rc, 0, info)
            self.assertIn('contacting node http://%s:' % address, info.replace('Pid', '\nPid'),
                          '%s not at %s: %s' % (node, address, info[-400:]))

    def test_3_board_state_reaches_hal_across_the_link(self):
        self.wait_nodes(['/hcl', '/hal'])
        rc, out = self.run_in(NS_STATION, STATION_IP, ['rostopic', 'echo', '-n', '5', '/hal/example_device/reading'],
                              timeout=40)
        self.assertEqual(rc, 0, out + self.logs())
        self.assertEqual(out.count('position:'), 5, out)

    def test_4_brain_command_reaches_the_firmware_across_the_link(self):
        # The example strategy lights the lamp from the dial: the emulator (robot side) must see
        # lamp PWM values the brain (station side) computed.
        self.wait_nodes(['/sim/firmware', '/hcl', '/hal', '/brain'])
        deadline = time.monotonic() + 40.0
        lamps = set()
        while time.monotonic() < deadline and len(lamps - {0}) < 3:
            rc, out = self.run_in(NS_ROBOT, ROBOT_IP, ['rostopic', 'echo', '-n', '10', '-p',
                                                       '/sim/example_board/firmware/lamp_pwm'], timeout=30)
            self.assertEqual(rc, 0, out)
            for line in out.splitlines()[1:]:
                lamps.add(int(line.split(',')[-1]))
        self.assertGreaterEqual(len(lamps - {0}), 3, 'lamp values seen by the firmware: %s%s' % (sorted(lamps), self.logs()))


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'product_distributed', DistributedTest, sys.argv)
