"""Two network namespaces of this machine joined by a veth pair and nothing else: the "two
computers" of the distributed tests (test_product_distributed.py, test_matches_cluster.py).
Needs root."""
import os
import signal
import subprocess


def ip(*args):
    subprocess.run(['ip'] + list(args), check=True, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)


def create(namespaces, veth, addresses):
    """namespaces[i] gets veth[i] with addresses[i]/30, and its loopback up."""
    for ns in namespaces:
        ip('netns', 'add', ns)
    ip('link', 'add', veth[0], 'type', 'veth', 'peer', 'name', veth[1])
    for ns, dev, addr in zip(namespaces, veth, addresses):
        ip('link', 'set', dev, 'netns', ns)
        ip('-n', ns, 'addr', 'add', addr + '/30', 'dev', dev)
        ip('-n', ns, 'link', 'set', dev, 'up')
        ip('-n', ns, 'link', 'set', 'lo', 'up')


def delete(namespaces):
    for ns in namespaces:
        subprocess.run(['ip', 'netns', 'del', ns], stderr=subprocess.DEVNULL)  # removes the veth too


def stop(proc):
    """A process started in a session of its own (start_new_session): Ctrl-C to its whole group,
    then SIGKILL if it is not gone within 15 s."""
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGINT)
        try:
            proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
