"""The config's computer/network, read one way for every Python reader: the nodes that judge who is
the robot (robot_network.RobotNetwork.from_param_server) and the installer (make install-robot,
robot_tools.install.plan.network_plan). The C++ twin is RobotNetwork::fromParams (command_gate.cpp).

    settings = read_network(Params.from_server('/computer').block('network'))
    -> {'address': '127.0.0.1', 'master_port': 11311, 'robot_hosts': ['10.0.0.2/32'], 'allow': [...]}

Strict: an unknown key, an address that is no IPv4 address of a computer, a port outside
1..65535, a robot_hosts or allow that is no list of IPv4 addresses or networks (a.b.c.d or
a.b.c.0/24, no host bits) is a ParameterError of one line naming the parameter.

    python3 -m robot_core.network_settings --describe   # its rows of the parameter tables
"""
import ipaddress
import re
import sys

from robot_core.params import ParameterError, Params, declaration_lines

COMPONENT = 'computer/network'  # the parameter tables' component name of this block
NETWORKS = 'IPv4 addresses or networks (a.b.c.d, a.b.c.0/24)'


# a.b.c.d or a.b.c.d/n, the one form the C++ twin (Ipv4Net::parse) reads too: no netmask form
_DOTTED = re.compile(r'^[0-9]{1,3}(\.[0-9]{1,3}){3}(/[0-9]{1,2})?$')


def ipv4_network(text):
    """An IPv4 address or CIDR network (no host bits set) as an IPv4Network; ValueError else."""
    if isinstance(text, bool) or not isinstance(text, (str, int)) or not _DOTTED.match(str(text).strip()):
        raise ValueError(text)
    return ipaddress.IPv4Network(str(text).strip(), strict=True)


def _refuse(params, key, reason):
    raise ParameterError('parameter %s: %s' % (params.qualified(key), reason))


def _address(params, value):
    try:
        if isinstance(value, bool) or not isinstance(value, (str, int)):
            raise ValueError(value)
        ip = ipaddress.IPv4Address(str(value).strip())
    except ValueError:
        _refuse(params, 'address', '%r is not an IPv4 address' % (value,))
    if ip.is_unspecified or ip.is_multicast:
        _refuse(params, 'address', '%s is not an address of the robot' % ip)
    return str(ip)


def _port(params, value):
    if not isinstance(value, int) or isinstance(value, bool) or not 1 <= value <= 65535:
        _refuse(params, 'master_port', '%r is not a port (1..65535)' % (value,))
    return value


def _networks(params, key, value):
    if value is None:  # `allow:` with nothing after it
        return []
    if not isinstance(value, list):
        _refuse(params, key, 'must be a list of IPv4 addresses or networks')
    out = []
    for entry in value:
        try:
            out.append(str(ipv4_network(entry)))
        except ValueError:
            _refuse(params, key, '%r is not an IPv4 address or network (a.b.c.d or a.b.c.0/24)' % (entry,))
    return out


def read_network(params):
    """computer/network from `params` (a Params over that block), with its defaults (loopback,
    11311, no other hosts): {'address': str, 'master_port': int, 'robot_hosts': [str],
    'allow': [str]} (networks written a.b.c.d/n). ParameterError names the first bad value."""
    address = params.value('address', '127.0.0.1', rule='an IPv4 address, not 0.0.0.0 or multicast',
                           meaning="the robot's own address: ROS_IP of its nodes, its master at "
                                   "http://address:master_port (loopback on one computer)")
    port = params.value('master_port', 11311, rule='1 .. 65535',
                        meaning="the ROS master's TCP port (ROS_MASTER_URI), opened by the firewall")
    hosts = params.value('robot_hosts', [], rule=NETWORKS,
                         meaning="the robot's other computers (two-computer deployment): their nodes are the "
                                 "robot's")
    allow = params.value('allow', [], rule=NETWORKS,
                         meaning='laptops let in (rviz, the team\'s tools): trusted, not the robot; for one '
                                 'match: make allow-laptop')
    # Checked before the values, as a misspelt key is the likelier mistake.
    known = params.declarations()
    unknown = sorted(k for k in map(str, params.keys()) if k not in known)
    if unknown:
        _refuse(params, unknown[0], 'unknown key (%s)' % ', '.join(sorted(known)))
    return {'address': _address(params, address), 'master_port': _port(params, port),
            'robot_hosts': _networks(params, 'robot_hosts', hosts), 'allow': _networks(params, 'allow', allow)}


def describe_lines():
    """What read_network declares, over an empty block (every default), as parameter-table rows."""
    params = Params({}, '/' + COMPONENT)
    read_network(params)
    return declaration_lines(params, lambda name: (COMPONENT, name))


def main(argv):
    if '--describe' not in argv:
        print('usage: python3 -m robot_core.network_settings --describe', file=sys.stderr)
        return 2
    print('\n'.join(describe_lines()))
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
