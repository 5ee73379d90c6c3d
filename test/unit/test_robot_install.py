"""make install-robot / uninstall-robot (scripts/robot_install.py) into a temporary staging root:
the files' contents against the values of config/ROBOT.yaml (read here, never copied), the units
through systemd-analyze verify, uninstall leaving the root empty, and the configuration errors
(exit 1 with one line). Nothing on this machine is touched: no systemctl, udevadm or ip. The
firewall's ruleset goes through `nft -c`, and is loaded, probed from outside and edited with
allow/deny only inside temporary network namespaces (root; skipped with the reason otherwise)."""
import copy
import ipaddress
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import yaml

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
SCRIPT = os.path.join(ROOT, 'scripts', 'robot_install.py')
from robot_tools.install import host_files, plan

ENV = dict(os.environ, PATH='/usr/bin:/bin:/usr/sbin:/sbin:' + os.environ.get('PATH', ''))


def config(robot):
    with open(os.path.join(ROOT, 'config', robot + '.yaml')) as f:
        return yaml.safe_load(f)


def run(*args, **kw):
    return subprocess.run([sys.executable, SCRIPT] + list(args), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          universal_newlines=True, env=ENV, **kw)


def unit(text):
    """{section: [(key, value), ...]} of a unit file."""
    out, section = {}, None
    for line in text.splitlines():
        line = line.strip()
        if not line or line.startswith('#'):
            continue
        if line.startswith('['):
            section = line.strip('[]')
            out.setdefault(section, [])
        else:
            key, value = line.split('=', 1)
            out[section].append((key, value))
    return out


def values(u, section, key):
    return [v for k, v in u.get(section, []) if k == key]


def network(cfg):
    """computer/network of a config, as the installer reads it (loopback when absent)."""
    n = dict(plan.DEFAULT_NETWORK)
    n.update((cfg.get('computer') or {}).get('network') or {})
    return n


def tree(root):
    return sorted(os.path.relpath(os.path.join(d, n), root) for d, dirs, files in os.walk(root) for n in dirs + files)


class InstallTest(unittest.TestCase):
    def setUp(self):
        self.root = tempfile.mkdtemp(prefix='robot_install_')

    def tearDown(self):
        shutil.rmtree(self.root, ignore_errors=True)

    def at(self, path):
        return os.path.join(self.root, path.lstrip('/'))

    def read(self, path):
        with open(self.at(path)) as f:
            return f.read()

    def install(self, robot):
        r = run('install', robot, '--root', self.root)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn('no systemctl, udevadm, ip or nft calls', r.stdout)
        return r

    def uninstall_leaves_root_empty(self, robot):
        r = run('uninstall', robot, '--root', self.root)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertEqual(tree(self.root), [], r.stdout)

    def check_robot(self, robot):
        cfg = config(robot)
        computer = cfg.get('computer') or {}
        can = {iface: spec['bitrate'] for iface, spec in (computer.get('can') or {}).items()}
        devices = computer.get('devices') or {}
        self.install(robot)
        units = '/etc/systemd/system'

        # The robot's service: its launch on the real robot, the workspace's environment.
        service = self.read('%s/robot-%s.service' % (units, robot))
        u = unit(service)
        exec_start = values(u, 'Service', 'ExecStart')
        self.assertEqual(len(exec_start), 1, service)
        self.assertIn('source %s/devel/setup.bash' % ROOT, exec_start[0])
        self.assertIn('exec roslaunch %s/launch/%s.launch sim:=false' % (ROOT, robot), exec_start[0])
        self.assertEqual(values(u, 'Service', 'Restart'), ['on-failure'])
        env = ' '.join(values(u, 'Service', 'Environment'))
        self.assertIn('PATH=/usr/bin:', env)
        self.assertIn('ROS_HOME=/var/lib/robot/%s/' % robot, env)
        self.assertIn('ROS_LOG_DIR=/var/lib/robot/%s/' % robot, env)
        self.assertEqual(values(u, 'Service', 'StandardOutput'), ['journal'])
        # The right to the real-time priorities the config asks for, and to lock memory.
        priorities = [(cfg.get(layer) or {}).get('realtime_priority', 0) for layer in ('hcl', 'hal')]
        self.assertEqual(values(u, 'Service', 'LimitRTPRIO'), [str(max(priorities))])
        self.assertEqual(values(u, 'Service', 'LimitMEMLOCK'), ['infinity'])
        after = ' '.join(values(u, 'Unit', 'After')).split()
        self.assertIn('network-online.target', after)
        for iface in can:
            self.assertIn('robot-can-%s.service' % iface, after)
        self.assertEqual(values(u, 'Install', 'WantedBy'), ['multi-user.target'])
        link = self.at('%s/multi-user.target.wants/robot-%s.service' % (units, robot))
        self.assertEqual(os.readlink(link), '%s/robot-%s.service' % (units, robot))   # enabled
        self.check_network(robot, cfg)

        # A oneshot unit per CAN interface, bound to and enabled for its device, at its bitrate.
        boards = plan.can_boards(cfg)
        self.assertEqual(set(boards.values()), set(can), 'computer/can != the hcl blocks\' socketcan buses')
        for iface, bitrate in can.items():
            u = unit(self.read('%s/robot-can-%s.service' % (units, iface)))
            device = 'sys-subsystem-net-devices-%s.device' % iface
            self.assertEqual(values(u, 'Unit', 'BindsTo'), [device])
            self.assertEqual(values(u, 'Service', 'Type'), ['oneshot'])
            self.assertEqual(values(u, 'Service', 'ExecStart'), [
                '-/sbin/ip link set %s down' % iface,
                '/sbin/ip link set %s type can bitrate %d restart-ms 100' % (iface, bitrate),
                '/sbin/ip link set %s up' % iface])
            self.assertEqual(values(u, 'Install', 'WantedBy'), [device])
            self.assertTrue(os.path.islink(self.at('%s/%s.wants/robot-can-%s.service' % (units, device, iface))))

        # udev: each device gets the name its board block uses.
        rules = '/etc/udev/rules.d/99-robot-%s.rules' % robot
        if devices:
            text = self.read(rules)
            lines = [l for l in text.splitlines() if l and not l.startswith('#')]
            self.assertEqual(len(lines), len(devices), text)
            for board, spec in devices.items():
                block = cfg['hcl'][board]
                path = block.get('port', block.get('device'))
                self.assertTrue(path.startswith('/dev/robot/'), path)
                rule = [l for l in lines if 'SYMLINK+="%s"' % path[len('/dev/'):] in l]
                self.assertEqual(len(rule), 1, text)
                self.assertIn('SUBSYSTEM=="%s"' % spec['subsystem'], rule[0])
                self.assertIn('ATTRS{idVendor}=="%s"' % spec['vendor'], rule[0])
                self.assertIn('ATTRS{idProduct}=="%s"' % spec['product'], rule[0])
                if spec['subsystem'] == 'input':
                    self.assertIn('KERNEL=="js*"', rule[0])
        else:
            self.assertFalse(os.path.exists(self.at(rules)))

        self.verify_units(robot)
        manifest = self.read('/var/lib/robot/%s/installed.txt' % robot)
        self.assertIn('file /etc/systemd/system/robot-%s.service' % robot, manifest)
        self.uninstall_leaves_root_empty(robot)

    def check_network(self, robot, cfg):
        """The service on the config's address, after and requiring its firewall; the ruleset is
        firewall_rules() of the config's network and this machine's ephemeral ports; the firewall
        unit loads it, its stop deletes the table, it is enabled."""
        net = network(cfg)
        units = '/etc/systemd/system'
        u = unit(self.read('%s/robot-%s.service' % (units, robot)))
        env = ' '.join(values(u, 'Service', 'Environment')).split()
        self.assertIn('ROS_IP=%s' % net['address'], env)
        self.assertIn('ROS_MASTER_URI=http://%s:%d' % (net['address'], net['master_port']), env)
        firewall = 'robot-firewall-%s.service' % robot
        self.assertEqual(values(u, 'Unit', 'Requires'), [firewall])
        self.assertIn(firewall, ' '.join(values(u, 'Unit', 'After')).split())

        nft_file = '/etc/robot/%s.nft' % robot
        rules = self.read(nft_file)
        self.assertEqual(rules, host_files.firewall_rules(robot, net, plan.read_port_range()))
        f = unit(self.read('%s/%s' % (units, firewall)))
        self.assertEqual(values(f, 'Service', 'Type'), ['oneshot'])
        self.assertEqual(values(f, 'Service', 'RemainAfterExit'), ['yes'])
        self.assertEqual(values(f, 'Service', 'ExecStart'), ['/usr/sbin/nft -f %s' % nft_file])
        self.assertEqual(values(f, 'Service', 'ExecStop'), ['-/usr/sbin/nft delete table inet robot_%s' % robot])
        self.assertIn('robot-%s.service' % robot, ' '.join(values(f, 'Unit', 'Before')).split())
        self.assertEqual(values(f, 'Install', 'WantedBy'), ['multi-user.target'])
        link = self.at('%s/multi-user.target.wants/%s' % (units, firewall))
        self.assertEqual(os.readlink(link), '%s/%s' % (units, firewall))   # enabled

    def verify_units(self, robot):
        """systemd-analyze verify: it works on unit files in any directory (it adds the file's
        directory to the search path), without a running systemd, and checks the directives and
        that ExecStart's programs exist. Its warnings exit 0: any output is a failure here."""
        if not shutil.which('systemd-analyze', path=ENV['PATH']):
            self.skipTest('no systemd-analyze here')
        units = self.at('/etc/systemd/system')
        files = sorted(os.path.join(units, f) for f in os.listdir(units) if f.endswith('.service'))
        r = subprocess.run(['systemd-analyze', 'verify'] + files, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           universal_newlines=True, env=ENV, cwd=units)
        # No sysinit.target etc. where systemd is not installed as a whole: that is the host, not us.
        problems = [l for l in r.stdout.splitlines() if 'robot-' in l or ':' in l and units in l]
        self.assertEqual((r.returncode, problems), (0, []), r.stdout)

    def test_eurobot2009(self):
        self.check_robot('eurobot2009')

    def test_logion(self):
        self.check_robot('logion')

    def test_skeleton_has_no_computer_section_just_the_service_and_its_firewall(self):
        self.assertNotIn('computer', config('skeleton'))
        self.install('skeleton')
        self.assertEqual(sorted(os.listdir(self.at('/etc/systemd/system'))),
                         ['multi-user.target.wants', 'robot-firewall-skeleton.service', 'robot-skeleton.service'])
        self.assertFalse(os.path.exists(self.at('/etc/udev')))
        # No computer/network: loopback, the master on 11311, only loopback allowed.
        env = ' '.join(values(unit(self.read('/etc/systemd/system/robot-skeleton.service')), 'Service', 'Environment'))
        self.assertIn('ROS_IP=127.0.0.1 ROS_MASTER_URI=http://127.0.0.1:11311', env)
        self.assertIn('elements = { 127.0.0.0/8 }', self.read('/etc/robot/skeleton.nft'))
        self.check_network('skeleton', config('skeleton'))
        self.verify_units('skeleton')
        self.uninstall_leaves_root_empty('skeleton')

    def test_dry_run_changes_nothing(self):
        r = run('install', 'eurobot2009', '--root', self.root, '--dry-run')
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn('would write /etc/systemd/system/robot-eurobot2009.service', r.stdout)
        self.assertIn('would write /etc/robot/eurobot2009.nft', r.stdout)
        self.assertEqual(tree(self.root), [])

    def test_reinstall_and_two_robots_share_the_root(self):
        self.install('eurobot2009')
        self.install('eurobot2009')
        self.install('logion')
        run('uninstall', 'eurobot2009', '--root', self.root)
        self.assertFalse(os.path.exists(self.at('/etc/systemd/system/robot-eurobot2009.service')))
        self.assertTrue(os.path.exists(self.at('/etc/systemd/system/robot-logion.service')))
        self.assertTrue(os.path.exists(self.at('/etc/udev/rules.d/99-robot-logion.rules')))
        self.assertTrue(os.path.exists(self.at('/etc/robot/logion.nft')))
        self.assertFalse(os.path.exists(self.at('/etc/robot/eurobot2009.nft')))
        r = run('uninstall', 'logion', '--root', self.root)
        self.assertEqual(r.returncode, 0, r.stderr)
        # The directories eurobot2009's install created and logion's used stay (empty): no file does.
        left = [p for p in tree(self.root) if not os.path.isdir(os.path.join(self.root, p))]
        self.assertEqual(left, [])
        self.assertFalse(os.path.exists(self.at('/var/lib/robot')), 'removed with the last robot')

    def test_uninstall_without_manifest_removes_what_install_would(self):
        self.install('eurobot2009')
        os.remove(self.at('/var/lib/robot/eurobot2009/installed.txt'))
        r = run('uninstall', 'eurobot2009', '--root', self.root)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn('no /var/lib/robot/eurobot2009/installed.txt', r.stdout)
        left = [p for p in tree(self.root) if not os.path.isdir(os.path.join(self.root, p))]
        self.assertEqual(left, [])

    def test_does_not_overwrite_a_file_it_did_not_install(self):
        path = self.at('/etc/systemd/system/robot-can-can0.service')
        os.makedirs(os.path.dirname(path))
        with open(path, 'w') as f:
            f.write('[Service]\nExecStart=/bin/true\n')
        r = run('install', 'eurobot2009', '--root', self.root)
        self.assertEqual(r.returncode, 1)
        self.assertIn('robot-can-can0.service exists and was not installed for eurobot2009', r.stderr)


class ConfigErrorTest(unittest.TestCase):
    """A wrong `computer:` section: exit 1, one line naming the value, nothing installed."""

    def setUp(self):
        self.repo = tempfile.mkdtemp(prefix='robot_install_repo_')
        os.mkdir(os.path.join(self.repo, 'config'))
        self.root = os.path.join(self.repo, 'root')

    def tearDown(self):
        shutil.rmtree(self.repo, ignore_errors=True)

    def refused(self, cfg, message):
        with open(os.path.join(self.repo, 'config', 'broken.yaml'), 'w') as f:
            yaml.safe_dump(cfg, f)
        r = run('install', 'broken', '--root', self.root, '--repo', self.repo)
        self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
        self.assertIn(message, r.stderr)
        self.assertFalse(os.path.exists(self.root) and tree(self.root), 'installed something')

    def test_can_bus_without_bitrate(self):
        cfg = copy.deepcopy(config('eurobot2009'))
        del cfg['computer']['can']['can0']
        board = sorted(plan.can_boards(cfg))[0]
        self.refused(cfg, 'hcl/%s/bus is socketcan://can0 but computer/can has no bitrate for can0' % board)

    def test_can_bus_and_no_computer_section(self):
        cfg = copy.deepcopy(config('eurobot2009'))
        del cfg['computer']
        self.refused(cfg, 'computer/can has no bitrate for can0')

    def test_bitrate_not_a_number(self):
        cfg = copy.deepcopy(config('eurobot2009'))
        cfg['computer']['can']['can0']['bitrate'] = '1M'
        self.refused(cfg, "computer/can/can0/bitrate: '1M' is not a bitrate")

    def test_realtime_priority_out_of_range(self):
        cfg = copy.deepcopy(config('eurobot2009'))
        cfg['hal']['realtime_priority'] = 120
        self.refused(cfg, 'hal/realtime_priority: 120 is not a priority 0..99')

    def test_device_of_no_board(self):
        cfg = copy.deepcopy(config('logion'))
        cfg['computer']['devices']['lidar'] = {'subsystem': 'tty', 'vendor': '10c4', 'product': 'ea60'}
        self.refused(cfg, 'computer/devices/lidar: there is no board block hcl/lidar')

    def test_device_path_not_under_dev(self):
        cfg = copy.deepcopy(config('logion'))
        cfg['hcl']['beacons']['port'] = '/tmp/beacons.tty'
        self.refused(cfg, "hcl/beacons/port is '/tmp/beacons.tty', not a path under /dev/")

    def test_bad_usb_id(self):
        cfg = copy.deepcopy(config('logion'))
        cfg['computer']['devices']['joystick']['vendor'] = 'logitech'
        self.refused(cfg, "computer/devices/joystick/vendor: 'logitech' is not a 4-digit hex USB id")

    def network_refused(self, key, value, message):
        cfg = copy.deepcopy(config('eurobot2009'))
        cfg['computer']['network'][key] = value
        self.refused(cfg, message)

    def test_address_not_ipv4(self):
        self.network_refused('address', 'robot.local', "computer/network/address: 'robot.local' is not an IPv4 address")
        self.network_refused('address', '::1', "computer/network/address: '::1' is not an IPv4 address")
        self.network_refused('address', '192.168.1.0/24', "'192.168.1.0/24' is not an IPv4 address")

    def test_address_everything(self):
        self.network_refused('address', '0.0.0.0', 'computer/network/address: 0.0.0.0 is not an address of the robot')

    def test_master_port_out_of_range(self):
        self.network_refused('master_port', 0, 'computer/network/master_port: 0 is not a port (1..65535)')
        self.network_refused('master_port', 65536, 'computer/network/master_port: 65536 is not a port (1..65535)')
        self.network_refused('master_port', '11311', "computer/network/master_port: '11311' is not a port")

    def test_allow_entry_not_ipv4(self):
        self.network_refused('allow', ['192.168.1.300'], "computer/network/allow: '192.168.1.300' is not an IPv4 "
                             "address or network")
        self.network_refused('allow', ['192.168.1.20/24'], "computer/network/allow: '192.168.1.20/24' is not")
        self.network_refused('robot_hosts', ['fe80::1'], "computer/network/robot_hosts: 'fe80::1' is not an IPv4")
        self.network_refused('allow', '192.168.1.20', 'computer/network/allow: must be a list')

    def test_network_unknown_key(self):
        self.network_refused('adress', '10.0.0.1', 'computer/network/adress: unknown key')


class FirewallRulesTest(unittest.TestCase):
    """firewall_rules(robot, network, port_range): the text, what it accepts and drops; nft -c."""

    def network(self, robot='eurobot2009', **extra):
        n = network(config(robot))
        n.update(extra)
        return n

    def rules(self, text):
        return [l.strip() for l in text.splitlines() if l.strip() and not l.strip().startswith('#')]

    def test_table_of_its_own_replaced_whole(self):
        for robot in ('eurobot2009', 'logion', 'skeleton'):
            lines = self.rules(host_files.firewall_rules(robot, self.network(robot), (32768, 60999)))
            self.assertEqual(lines[:3], ['table inet robot_%s' % robot, 'delete table inet robot_%s' % robot,
                                         'table inet robot_%s {' % robot])
            self.assertNotIn('flush ruleset', '\n'.join(lines))

    def test_accepted_and_dropped(self):
        net = self.network(robot_hosts=['10.1.0.2'], allow=['192.168.1.20', '192.168.7.0/24'])
        low, high = 40000, 50000
        text = host_files.firewall_rules('eurobot2009', net, (low, high))
        lines = self.rules(text)
        elements = [l for l in lines if l.startswith('elements = {')]
        self.assertEqual(len(elements), 1, text)
        got = set(e.strip() for e in elements[0][len('elements = {'):].rstrip('}').split(','))
        want = set(['127.0.0.0/8', '10.1.0.2', '192.168.1.20', '192.168.7.0/24'])
        if not ipaddress.ip_address(net['address']).is_loopback:
            want.add(net['address'])
        self.assertEqual(got, want)
        self.assertIn('type ipv4_addr', lines)
        self.assertIn('flags interval', lines)
        self.assertIn('counter ros_dropped {', lines)
        self.assertIn('type filter hook input priority filter; policy accept;', lines)
        chain = lines[lines.index('chain input {') + 2:]
        self.assertEqual(chain[:2], ['iif "lo" accept', 'ct state established,related accept'])
        port = net['master_port']
        ports = [('tcp', str(port)), ('tcp', '%d-%d' % (low, high)), ('udp', '%d-%d' % (low, high))]
        for proto, p in ports:
            accept = [l for l in chain if l.startswith('%s dport %s ip saddr @allowed accept' % (proto, p))]
            drop = '%s dport %s counter name "ros_dropped" drop' % (proto, p)
            self.assertEqual(len(accept), 1, text)
            self.assertIn(drop, chain)
            self.assertLess(chain.index(accept[0]), chain.index(drop))
        # Nothing else is dropped: ssh and the rest stay untouched.
        self.assertEqual(len([l for l in chain if 'drop' in l]), 3, text)

    def test_overlaps_merged(self):
        # An interval set refuses overlapping elements: loopback's own address, a host inside an allowed network.
        net = self.network(address='127.0.0.1', robot_hosts=['192.168.7.5'], allow=['192.168.7.0/24', '192.168.7.0/25'])
        self.assertEqual(host_files.allowed_elements(net), ['127.0.0.0/8', '192.168.7.0/24'])

    def test_port_range_reader(self):
        d = tempfile.mkdtemp(prefix='robot_install_ports_')
        try:
            path = os.path.join(d, 'ip_local_port_range')
            with open(path, 'w') as f:
                f.write('32768\t60999\n')
            self.assertEqual(plan.read_port_range(path), (32768, 60999))
            self.assertEqual(plan.read_port_range(os.path.join(d, 'none')), (32768, 60999))
            with open(path, 'w') as f:
                f.write('60999 1024\n')
            self.assertRaises(plan.ConfigError, plan.read_port_range, path)
        finally:
            shutil.rmtree(d)
        with open('/proc/sys/net/ipv4/ip_local_port_range') as f:
            self.assertEqual(plan.read_port_range(), tuple(int(v) for v in f.read().split()))

    def test_nft_checks_it(self):
        """nft -c parses and checks it against the kernel without loading it (needs CAP_NET_ADMIN)."""
        if not os.path.exists('/usr/sbin/nft'):
            self.skipTest('no /usr/sbin/nft (apt-get install nftables)')
        if os.geteuid() != 0:
            self.skipTest('nft -c needs root (netlink)')
        for robot in ('eurobot2009', 'logion', 'skeleton'):
            net = self.network(robot, allow=['192.168.1.20', '10.0.0.0/8'])
            with tempfile.NamedTemporaryFile('w', suffix='.nft') as f:
                f.write(host_files.firewall_rules(robot, net, plan.read_port_range()))
                f.flush()
                r = subprocess.run(['/usr/sbin/nft', '-c', '-f', f.name], stdout=subprocess.PIPE,
                                   stderr=subprocess.STDOUT, universal_newlines=True)
                self.assertEqual(r.returncode, 0, r.stdout)


def netns(test, name):
    """A network namespace for this test (deleted at cleanup), its loopback up; skips the test when
    one cannot be made here."""
    if os.geteuid() != 0 or not os.path.exists('/usr/sbin/nft') or not shutil.which('ip', path=ENV['PATH']):
        test.skipTest('needs root, ip and /usr/sbin/nft for a network namespace')
    name = '%s_%d' % (name, os.getpid())
    r = subprocess.run(['ip', 'netns', 'add', name], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       universal_newlines=True, env=ENV)
    if r.returncode:
        test.skipTest('cannot make a network namespace here: %s' % r.stdout.strip())
    test.addCleanup(subprocess.call, ['ip', 'netns', 'delete', name], env=ENV)
    subprocess.check_call(['ip', '-n', name, 'link', 'set', 'lo', 'up'], env=ENV)
    return name


def in_ns(ns, *cmd, **kw):
    return subprocess.run(['ip', 'netns', 'exec', ns] + list(cmd), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          universal_newlines=True, env=ENV, **kw)


CONNECT = 'import socket, sys; socket.create_connection((sys.argv[1], int(sys.argv[2])), timeout=1.5).close()'
LISTEN = """import socket, sys, time
ss = []
for p in sys.argv[1:]:
    s = socket.socket(); s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    s.bind(('0.0.0.0', int(p))); s.listen(16); s.setblocking(False); ss.append(s)
print('listening', flush=True)
while True:
    for s in ss:
        try:
            s.accept()[0].close()
        except BlockingIOError:
            pass
    time.sleep(0.02)
"""


class FirewallLoadedTest(unittest.TestCase):
    """The ruleset loaded in a network namespace (this machine's own ruleset is never touched),
    probed from a second one over a veth pair; allow/deny/status edit it there."""

    def load(self, ns, robot, net):
        d = tempfile.mkdtemp(prefix='robot_install_nft_')
        self.addCleanup(shutil.rmtree, d, True)
        path = os.path.join(d, robot + '.nft')
        with open(path, 'w') as f:
            f.write(host_files.firewall_rules(robot, net, plan.read_port_range()))
        for _ in range(2):   # twice: loading it again replaces the table
            r = in_ns(ns, '/usr/sbin/nft', '-f', path)
            self.assertEqual(r.returncode, 0, r.stderr)
        r = in_ns(ns, '/usr/sbin/nft', 'list', 'table', 'inet', 'robot_' + robot)
        self.assertEqual(r.returncode, 0, r.stderr)
        return r.stdout

    def test_loads_in_a_namespace(self):
        ns = netns(self, 'rinst_load')
        for robot in ('eurobot2009', 'logion', 'skeleton'):
            net = network(config(robot))
            listed = self.load(ns, robot, net)
            self.assertIn('set allowed {', listed)
            self.assertIn('127.0.0.0/8', listed)
            self.assertIn('counter ros_dropped {', listed)
            self.assertIn('tcp dport %d counter name "ros_dropped" drop' % net['master_port'], listed)
            self.assertEqual(listed.count('table inet robot_%s' % robot), 1)
        tables = in_ns(ns, '/usr/sbin/nft', 'list', 'tables').stdout.split()
        self.assertEqual(sorted(t for t in tables if t.startswith('robot_')),
                         ['robot_eurobot2009', 'robot_logion', 'robot_skeleton'])

    def test_outsider_dropped_and_counted_until_allowed(self):
        robot = 'eurobot2009'
        net = network(config(robot))
        inside, outside = netns(self, 'rinst_robot'), netns(self, 'rinst_pits')
        veth = 'rinst%d' % (os.getpid() % 100000)
        subprocess.check_call(['ip', 'link', 'add', veth + 'a', 'netns', inside, 'type', 'veth',
                               'peer', 'name', veth + 'b', 'netns', outside], env=ENV)
        robot_ip, pits_ip = '10.213.0.1', '10.213.0.2'
        for ns, dev, ip in ((inside, veth + 'a', robot_ip), (outside, veth + 'b', pits_ip)):
            subprocess.check_call(['ip', '-n', ns, 'addr', 'add', ip + '/30', 'dev', dev], env=ENV)
            subprocess.check_call(['ip', '-n', ns, 'link', 'set', dev, 'up'], env=ENV)
        self.load(ns=inside, robot=robot, net=net)
        low, high = plan.read_port_range()
        ros_port, other_port = net['master_port'], 2222   # 2222: not a ROS port (an ssh)
        listener = subprocess.Popen(['ip', 'netns', 'exec', inside, sys.executable, '-c', LISTEN, str(ros_port),
                                     str(other_port), str(low + 7)], stdout=subprocess.PIPE, env=ENV,
                                    universal_newlines=True)
        self.addCleanup(listener.stdout.close)
        self.addCleanup(listener.wait)
        self.addCleanup(listener.kill)
        self.assertEqual(listener.stdout.readline().strip(), 'listening')

        def run_in(ns, *args):
            return in_ns(ns, sys.executable, SCRIPT, *args)

        def reaches(port):
            return in_ns(outside, sys.executable, '-c', CONNECT, robot_ip, str(port)).returncode == 0

        def dropped():
            r = run_in(inside, 'status', robot)
            self.assertEqual(r.returncode, 0, r.stderr)
            return int(r.stdout.split('ros_dropped: ')[1].split()[0])

        def allowed(stdout):
            return stdout.split('allowed to the ROS ports: ')[1].splitlines()[0].split(', ')

        self.assertTrue(reaches(other_port), 'a port not ROS\'s is untouched')
        self.assertEqual(dropped(), 0)
        self.assertFalse(reaches(ros_port), 'the master port reached from outside')
        self.assertFalse(reaches(low + 7), 'a node port reached from outside')
        self.assertGreaterEqual(dropped(), 2)
        self.assertEqual(in_ns(inside, sys.executable, '-c', CONNECT, '127.0.0.1', str(ros_port)).returncode, 0)

        r = run_in(inside, 'allow', robot, pits_ip)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn(pits_ip, allowed(r.stdout))
        self.assertTrue(reaches(ros_port), 'the allowed laptop does not reach the master')
        self.assertTrue(reaches(low + 7), 'the allowed laptop does not reach a node')
        r = run_in(inside, 'allow', robot, pits_ip)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn('already allowed', r.stdout)

        r = run_in(inside, 'deny', robot, pits_ip)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertNotIn(pits_ip, allowed(r.stdout))
        before = dropped()
        self.assertFalse(reaches(ros_port), 'denied, and still reaches the master')
        self.assertGreater(dropped(), before)
        # Loopback is part of the robot: not something deny takes out.
        r = run_in(inside, 'deny', robot, '127.0.0.1')
        self.assertEqual(r.returncode, 1, r.stdout)
        self.assertIn('127.0.0.1 is allowed as part of 127.0.0.0/8', r.stderr)

    def test_allow_without_the_firewall(self):
        ns = netns(self, 'rinst_none')
        for args in (('allow', 'eurobot2009', '192.168.1.20'), ('deny', 'eurobot2009', '192.168.1.20'),
                     ('status', 'eurobot2009')):
            r = in_ns(ns, sys.executable, SCRIPT, *args)
            self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
            self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
            self.assertIn('the firewall of eurobot2009 is not installed/running', r.stderr)
            self.assertIn('make install-robot ROBOT=eurobot2009', r.stderr)


class SubcommandArgsTest(unittest.TestCase):
    """allow/deny/status refuse a bad address before touching anything; the Makefile's targets."""

    def test_bad_address(self):
        r = run('allow', 'eurobot2009', 'laptop.local')
        self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
        self.assertIn("'laptop.local' is not an IPv4 address or network", r.stderr)

    def test_address_required(self):
        self.assertEqual(run('allow', 'eurobot2009').returncode, 2)
        self.assertEqual(run('status', 'eurobot2009', '10.0.0.1').returncode, 2)

    def test_make_targets(self):
        if not shutil.which('make', path=ENV['PATH']):
            self.skipTest('no make')
        for target, args in (('allow-laptop', 'allow eurobot2009 192.168.1.20'),
                             ('deny-laptop', 'deny eurobot2009 192.168.1.20'),
                             ('firewall-status', 'status eurobot2009')):
            r = subprocess.run(['make', '-n', '-C', ROOT, target, 'ROBOT=eurobot2009', 'ADDR=192.168.1.20'],
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True, env=ENV)
            self.assertEqual(r.returncode, 0, r.stdout)
            self.assertIn('scripts/robot_install.py %s' % args, r.stdout)
        r = subprocess.run(['make', '-C', ROOT, 'allow-laptop', 'ROBOT=eurobot2009'], stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, universal_newlines=True, env=ENV)
        self.assertEqual(r.returncode, 2, r.stdout)
        self.assertIn('ADDR=', r.stdout)


if __name__ == '__main__':
    unittest.main()
