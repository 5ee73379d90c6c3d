#!/usr/bin/env python3
"""Helper of scripts/bench/can.sh (see there). Starts its own master, emulators and drivers."""
import os
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time

import yaml

ROOT = sys.argv[1] if len(sys.argv) > 1 else '.'
PORT = 27020
BUS = 'udp://127.0.0.1:%d' % PORT
CAN_TYPES = {'MotorBoard', 'StepperBoard', 'ServoBoard', 'Epos', 'HmiBoard'}


def free_port():
    s = socket.socket()
    s.bind(('127.0.0.1', 0))
    p = s.getsockname()[1]
    s.close()
    return p


def pct(xs, q):
    xs = sorted(xs)
    return xs[min(len(xs) - 1, int(q / 100.0 * len(xs)))] if xs else float('nan')


def frame_bits(dlc, rtr):
    """Bits of a standard CAN 2.0A frame on the wire: 47 + 8n nominal; bit stuffing adds up to
    (34 + 8n - 1) / 4 more (worst case)."""
    n = 0 if rtr else dlc
    return 47 + 8 * n, 47 + 8 * n + (34 + 8 * n - 1) // 4


class Run(object):
    """A master, the emulators and hcl_node with the given blocks; can_dump and subscribers."""

    def __init__(self, boards, emulators, seconds):
        self.env = dict(os.environ)
        self.env['ROS_MASTER_URI'] = 'http://127.0.0.1:%d' % free_port()
        self.env['ROS_HOSTNAME'] = '127.0.0.1'
        os.environ.update(self.env)
        self.procs = []
        RUNS.append(self)
        self.tmp = tempfile.mkdtemp(prefix='can_bench_')
        with open(os.path.join(self.tmp, 'p.yaml'), 'w') as f:
            yaml.safe_dump({'hcl': boards, 'firmware': emulators}, f)
        port = int(self.env['ROS_MASTER_URI'].rsplit(':', 1)[1])
        self.spawn(['rosmaster', '--core', '-p', str(port)])
        for _ in range(100):
            try:
                socket.create_connection(('127.0.0.1', port), 0.2).close()
                break
            except OSError:
                time.sleep(0.1)
        subprocess.check_call(['rosparam', 'load', os.path.join(self.tmp, 'p.yaml'), '/'], env=self.env)
        self.spawn(['rosrun', 'robot_sim', 'firmware_host', '__name:=firmware'])
        self.spawn(['rosrun', 'hcl_drivers', 'hcl_node', '__name:=hcl'])
        self.seconds = seconds

    def spawn(self, cmd, **kw):
        p = subprocess.Popen(cmd, env=self.env, stdout=kw.get('stdout', subprocess.DEVNULL),
                             stderr=subprocess.DEVNULL, preexec_fn=os.setsid)
        self.procs.append(p)
        return p

    def measure(self, topics):
        import rospy
        from diagnostic_msgs.msg import DiagnosticArray
        import importlib
        rospy.init_node('can_bench', anonymous=True, disable_signals=True)
        arrivals = {t: [] for t in topics}
        diag = {}
        subs = []
        for t, (pkg, typ) in topics.items():
            cls = getattr(importlib.import_module(pkg + '.msg'), typ)
            subs.append(rospy.Subscriber(
                t, cls, lambda m, t=t: arrivals[t].append((time.time(), m.header.stamp.to_sec())), queue_size=2000,
                tcp_nodelay=True))

        def on_diag(a):
            for s in a.status:
                diag[s.hardware_id] = {kv.key: kv.value for kv in s.values}
        subs.append(rospy.Subscriber('/diagnostics', DiagnosticArray, on_diag))
        time.sleep(4.0)  # everyone started, configured, answering
        for v in arrivals.values():
            del v[:]
        dump = os.path.join(self.tmp, 'dump.txt')
        with open(dump, 'w') as out:
            d = self.spawn(['rosrun', 'hcl_drivers', 'can_dump', BUS, str(self.seconds)], stdout=out)
            t0 = time.time()
            d.wait()
        t1 = time.time()
        for s in subs:
            s.unregister()
        frames = []
        with open(dump) as f:
            for line in f:
                parts = line.split()
                if len(parts) != 3:
                    continue
                ts = float(parts[0].strip('()'))
                cid, data = parts[2].split('#')
                rtr = data.startswith('R')
                dlc = int(data[1:] or 0) if rtr else len(data) // 2
                frames.append((ts, int(cid, 16), rtr, dlc))
        # Rates and counts over the span the dump really covers.
        if frames:
            t0, t1 = frames[0][0], frames[-1][0]
            for k in arrivals:
                arrivals[k] = [a for a in arrivals[k] if t0 <= a[1] <= t1]
        return frames, arrivals, diag, (t0, t1)

    def close(self):
        procs, self.procs = self.procs, []
        for p in reversed(procs):
            try:
                os.killpg(p.pid, signal.SIGINT)
            except OSError:
                pass
        for p in reversed(procs):
            try:
                p.wait(5)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)


RUNS = []


def cleanup(*_):
    # Never leave the bench's processes behind (timeout's SIGTERM, Ctrl-C, errors).
    for r in RUNS:
        r.close()
    os._exit(1)


def latencies(frames, rtr_id, arrivals, which=1):
    """For each state message, the time from the last RTR on rtr_id before it to its publication
    (which=1: header stamp, set when the driver publishes) or to its arrival at a Python
    subscriber (which=0) [ms]. Both clocks are the machine's wall clock."""
    rtrs = [f[0] for f in frames if f[1] == rtr_id and f[2]]
    out, i = [], 0
    for t in sorted(a[which] for a in arrivals):
        while i + 1 < len(rtrs) and rtrs[i + 1] <= t:
            i += 1
        if rtrs and rtrs[i] <= t and t - rtrs[i] < 0.5:
            out.append(1e3 * (t - rtrs[i]))
    return out


def load_config():
    with open(os.path.join(ROOT, 'config/eurobot2009.yaml')) as f:
        robot = yaml.safe_load(f)
    with open(os.path.join(ROOT, 'config/eurobot2009.sim.yaml')) as f:
        sim = yaml.safe_load(f)
    boards = {k: dict(v, bus=BUS) for k, v in robot['hcl'].items() if isinstance(v, dict) and v.get('type') in CAN_TYPES}
    emus = {k: dict(v, bus=BUS) for k, v in sim['sim']['firmware'].items()
            if isinstance(v, dict) and v.get('type') in CAN_TYPES}  # an emulator has its board's name
    return boards, emus


def all_boards():
    boards, emus = load_config()
    run = Run(boards, emus, 10.0)
    try:
        topics = {}
        types = {'MotorBoard': 'MotorBoardState', 'StepperBoard': 'StepperBoardState', 'ServoBoard': 'ServoBoardState',
                 'Epos': 'EposState', 'HmiBoard': 'HmiBoardState'}
        for name, b in boards.items():
            topics['/hcl/%s/state' % name] = ('hcl_drivers', types[b['type']])
        frames, arrivals, diag, (t0, t1) = run.measure(topics)
    finally:
        run.close()
    span = t1 - t0
    print('CAN-over-UDP, all five boards together (%d frames in %.1f s):' % (len(frames), span))
    total_cfg = total_ach = 0.0
    for name, b in sorted(boards.items()):
        d = diag.get('/hcl/%s' % name, {})
        ach = float(d.get('achieved rate [Hz]', 'nan'))
        states = len(arrivals['/hcl/%s/state' % name]) / span
        total_cfg += float(b['rate'])
        total_ach += ach
        print('  %-14s configured %6.1f Hz  achieved %7.2f Hz  (state msgs %7.2f /s)  errors %s' %
              (name, float(b['rate']), ach, states, d.get('errors', '?')))
    print('  total polls    configured %6.1f /s  achieved %7.2f /s' % (total_cfg, total_ach))
    # RTR -> state latency per board (first RTR COB-ID of each board's poll)
    first_rtr = {'MotorBoard': lambda n: 0x180 + n, 'StepperBoard': lambda n: 0x180 + n,
                 'ServoBoard': lambda n: 0x180 + n, 'Epos': lambda n: 0x180 + n, 'HmiBoard': lambda n: 0x180 + n}
    allat, allsub = [], []
    for name, b in sorted(boards.items()):
        cob = int(b.get('status_cob_id', 0)) if b['type'] == 'Epos' and b.get('status_cob_id') else first_rtr[b['type']](int(b['node_id']))
        lat = latencies(frames, cob, arrivals['/hcl/%s/state' % name])
        sub = latencies(frames, cob, arrivals['/hcl/%s/state' % name], 0)
        allat += lat
        allsub += sub
        print('  %-14s RTR 0x%03X -> ~state published: p50 %.3f ms  p99 %.3f ms (n=%d);  -> received by a rospy '
              'subscriber: p50 %.3f ms  p99 %.3f ms' % (name, cob, pct(lat, 50), pct(lat, 99), len(lat), pct(sub, 50),
                                                        pct(sub, 99)))
    print('  all boards     RTR -> ~state published: p50 %.3f ms  p99 %.3f ms;  -> rospy subscriber: p50 %.3f ms  '
          'p99 %.3f ms' % (pct(allat, 50), pct(allat, 99), pct(allsub, 50), pct(allsub, 99)))
    nominal = sum(frame_bits(f[3], f[2])[0] for f in frames) / span
    stuffed = sum(frame_bits(f[3], f[2])[1] for f in frames) / span
    print('  bus load at 1 Mbit/s: %.2f %% nominal, %.2f %% with worst-case bit stuffing (%.0f frames/s)' %
          (nominal / 1e4, stuffed / 1e4, len(frames) / span))


def jitter(rate):
    boards, emus = load_config()
    mb = dict(boards['motor_board'], rate=rate, loop='bench')
    run = Run({'motor_board': mb}, {'motor_board': emus['motor_board']}, 6.0)
    try:
        frames, arrivals, diag, (t0, t1) = run.measure({'/hcl/motor_board/state': ('hcl_drivers', 'MotorBoardState')})
    finally:
        run.close()
    cob = 0x180 + int(mb['node_id'])
    rtrs = [f[0] for f in frames if f[1] == cob and f[2]]
    periods = [b - a for a, b in zip(rtrs, rtrs[1:])]
    err = [1e3 * abs(p - 1.0 / rate) for p in periods]
    d = diag.get('/hcl/motor_board', {})
    lat = latencies(frames, cob, arrivals['/hcl/motor_board/state'])
    print('motor board alone at %4d Hz: achieved %.1f Hz (diagnostics %s Hz), poll jitter |period - %.2f ms|: '
          'p50 %.3f ms  p99 %.3f ms  max %.3f ms; RTR -> ~state published p50 %.3f ms p99 %.3f ms; errors %s' %
          (rate, len(rtrs) / (t1 - t0), d.get('achieved rate [Hz]', '?'), 1e3 / rate, pct(err, 50), pct(err, 99),
           max(err) if err else float('nan'), pct(lat, 50), pct(lat, 99), d.get('errors', '?')))


if __name__ == '__main__':
    # One phase per process: rospy initialises once per process, each phase has its own master.
    phase = sys.argv[2] if len(sys.argv) > 2 else 'all'
    signal.signal(signal.SIGTERM, cleanup)
    signal.signal(signal.SIGINT, cleanup)
    if phase == 'all':
        all_boards()
    elif phase == 'vcan':
        print('vcan: not measured here (this kernel has no AF_CAN); the SocketCAN path is tested in a VM '
          '(scripts/can_socketcan_vm_test.sh) where software emulation distorts timing.')
    else:
        jitter(int(phase))
