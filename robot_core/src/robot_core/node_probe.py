"""Is a ROS node's process alive? Its pid over its XML-RPC API, with a reply window (what
`rosnode ping` does): a node killed -9 stays registered with the master but refuses the
connection; a stalled one (SIGSTOP, a deadlocked spinner) accepts it and never answers."""
import socket
import xmlrpc.client

import rosgraph


class _TimeoutTransport(xmlrpc.client.Transport):
    def __init__(self, timeout):
        super().__init__()
        self._timeout = timeout

    def make_connection(self, host):
        conn = super().make_connection(host)
        conn.timeout = self._timeout
        return conn


def probe(master, node, timeout, caller, uri=None):
    """(pid, None) when `node` answers getPid within `timeout` wall seconds, else (None, why).
    `master`: a rosgraph.Master; `caller`: the asking node's name; `uri`: the node's XML-RPC URI
    when the caller knows it (saves asking the master; a respawned node has a new one)."""
    if uri is None:
        try:
            uri = master.lookupNode(node)
        except rosgraph.MasterError:
            return None, 'not registered with the master'
        except (socket.error, OSError) as e:
            return None, 'ROS master unreachable: %s' % e
    try:
        code, msg, pid = xmlrpc.client.ServerProxy(uri, transport=_TimeoutTransport(timeout)).getPid(caller)
    except socket.timeout:
        return None, 'not answering within %.2f s (stalled)' % timeout
    except (socket.error, OSError) as e:
        return None, 'process gone (%s)' % (getattr(e, 'strerror', None) or e)
    except xmlrpc.client.Error as e:
        return None, 'bad XML-RPC reply: %s' % e
    if code != 1:
        return None, 'getPid failed: %s' % msg
    return pid, None
