"""The running firewall of a robot (its nftables table inet robot_ROBOT, loaded by
make install-robot): its allow-list changed for one match until the next reboot or reload
(make allow-laptop / deny-laptop) and its status (the set `allowed`, the ros_dropped counter)."""
import os
import re
import subprocess
import sys

from robot_core.network_settings import ipv4_network

from robot_tools.install.host_files import NFT, firewall_unit_name, table_name
from robot_tools.install.plan import ConfigError


# ---- the running firewall: the allow-list for one match (not persistent) ----

def nft(*args):
    """(returncode, output) of nft ARGS on this machine (its current network namespace)."""
    try:
        r = subprocess.run([NFT] + list(args), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           universal_newlines=True)
    except OSError as e:
        return 127, str(e)
    return r.returncode, r.stdout


def table_loaded(robot):
    return nft('list', 'table', 'inet', table_name(robot))[0] == 0


def require_table(robot):
    if not os.path.exists(NFT):
        raise ConfigError('%s missing: apt-get install nftables (make deps), then make install-robot ROBOT=%s'
                          % (NFT, robot))
    if not table_loaded(robot):
        raise ConfigError('the firewall of %s is not installed/running (no nftables table inet %s): '
                          'make install-robot ROBOT=%s, or systemctl start %s'
                          % (robot, table_name(robot), robot, firewall_unit_name(robot)))


def element(addr):
    try:
        net = ipv4_network(addr)
    except ValueError:
        raise ConfigError('%r is not an IPv4 address or network (a.b.c.d or a.b.c.0/24)' % addr)
    return str(net) if net.prefixlen < 32 else str(net.network_address)


def covering(robot, elem):
    """The element of the running set `allowed` that holds elem, or None."""
    rc, out = nft('get', 'element', 'inet', table_name(robot), 'allowed', '{', elem, '}')
    if rc:
        return None
    m = re.search(r'elements\s*=\s*\{\s*([^}]*?)\s*\}', out)
    return m.group(1) if m else elem


def status(robot, out=sys.stdout):
    """Prints the running set `allowed` and the ros_dropped counter; returns (elements, packets, bytes)."""
    require_table(robot)
    table = table_name(robot)
    rc, text = nft('list', 'set', 'inet', table, 'allowed')
    m = re.search(r'elements\s*=\s*\{([^}]*)\}', text)
    elements = [e.strip() for e in m.group(1).split(',')] if m else []
    rc, text = nft('list', 'counter', 'inet', table, 'ros_dropped')
    m = re.search(r'packets\s+(\d+)\s+bytes\s+(\d+)', text)
    packets, nbytes = (int(m.group(1)), int(m.group(2))) if m else (0, 0)
    out.write('firewall of %s (nftables table inet %s):\n' % (robot, table))
    out.write('  allowed to the ROS ports: %s\n' % (', '.join(elements) or '(none)'))
    out.write('  ros_dropped: %d packets, %d bytes (to the ROS ports from anywhere else)\n' % (packets, nbytes))
    return elements, packets, nbytes


def allow(robot, addr, out=sys.stdout):
    """Adds addr to the running set `allowed` (until the firewall is reloaded or the computer reboots)."""
    elem = element(addr)
    require_table(robot)
    held = covering(robot, elem)
    if held is not None:
        out.write('%s is already allowed (%s)\n' % (elem, held))
    else:
        rc, text = nft('add', 'element', 'inet', table_name(robot), 'allowed', '{', elem, '}')
        if rc:
            raise ConfigError('nft add element %s: %s' % (elem, ' '.join(text.split())))
        out.write('allowed %s until the next reboot or reinstall (make deny-laptop ROBOT=%s ADDR=%s takes it '
                  'out)\n' % (elem, robot, addr))
    return status(robot, out)


def deny(robot, addr, out=sys.stdout):
    """Deletes addr from the running set `allowed`; connections already open stay until closed."""
    elem = element(addr)
    require_table(robot)
    held = covering(robot, elem)
    if held is None:
        out.write('%s was not allowed\n' % elem)
    elif held != elem:
        raise ConfigError('%s is allowed as part of %s (loopback, the robot\'s own addresses or '
                          'config/%s.yaml computer/network/allow): change the config and make install-robot'
                          % (elem, held, robot))
    else:
        rc, text = nft('delete', 'element', 'inet', table_name(robot), 'allowed', '{', elem, '}')
        if rc:
            raise ConfigError('nft delete element %s: %s' % (elem, ' '.join(text.split())))
        out.write('denied %s (its connections already open stay until they close; systemctl restart '
                  'robot-%s closes them)\n' % (elem, robot))
    return status(robot, out)
