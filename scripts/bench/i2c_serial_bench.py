#!/usr/bin/env python3
"""Figures for scripts/bench/i2c_serial.sh (see there). Own ROS master on port 27290."""
import os
import subprocess
import sys
import tempfile
import threading
import time

import yaml

ROOT = sys.argv[1] if len(sys.argv) > 1 else os.getcwd()
PORT = 27290
os.environ['ROS_MASTER_URI'] = 'http://127.0.0.1:%d' % PORT
I2C_TYPES = {'HBMotor', 'MCP23016', 'SRF02', 'CMPS03'}  # the boards' names, which their emulators share
MEASURE_S = 6.0


def percentile(xs, p):
    xs = sorted(xs)
    return xs[min(len(xs) - 1, int(round(p / 100.0 * (len(xs) - 1))))] if xs else float('nan')


def main():
    tmp = tempfile.mkdtemp(prefix='i2c_bench_', dir='/tmp')
    bus = 'sim://%s/i2c-1' % tmp
    tty = '%s/beacons.tty' % tmp
    cfg = yaml.safe_load(open(os.path.join(ROOT, 'config/logion.yaml')))['hcl']
    hcl, fw = {}, {}
    for name, block in cfg.items():
        if isinstance(block, dict) and block.get('type') in I2C_TYPES:
            hcl[name] = dict(block, bus=bus)
            fw[name] = {'type': block['type'], 'bus': bus, 'address': block['address']}
    beacons = dict(cfg['beacons'], port=tty)
    hcl['beacons'] = beacons
    fw['beacons'] = {'type': 'BeaconReceiver', 'port': tty, 'period': 0.01}
    params = os.path.join(tmp, 'params.yaml')
    yaml.safe_dump({'hcl': hcl, 'sim': {'firmware': fw}}, open(params, 'w'))
    procs = []
    devnull = open(os.devnull, 'w')
    try:
        procs.append(subprocess.Popen(['roscore', '-p', str(PORT)], stdout=devnull, stderr=devnull))
        import rosgraph
        end = time.time() + 30
        while not rosgraph.is_master_online() and time.time() < end:
            time.sleep(0.2)
        subprocess.check_call(['rosparam', 'load', params])
        procs.append(subprocess.Popen(['rosrun', 'robot_sim', 'firmware_host', '__name:=firmware', '__ns:=/sim'],
                                      stdout=devnull, stderr=devnull))
        procs.append(subprocess.Popen(['rosrun', 'hcl_drivers', 'hcl_node', '__name:=hcl'], stdout=devnull, stderr=devnull))
        import rospy
        from diagnostic_msgs.msg import DiagnosticArray
        from hcl_drivers.msg import BeaconReceiverState
        from std_msgs.msg import Float64MultiArray
        rospy.init_node('i2c_serial_bench', disable_signals=True)
        lock = threading.Lock()
        diag = {}
        sent = {}
        latencies, read_latencies = [], []

        def on_diag(arr):
            with lock:
                for s in arr.status:
                    diag[s.name] = s

        def on_sent(m):
            with lock:
                sent[(int(m.data[0]), int(m.data[1]))] = m.data[3]

        def on_state(s):
            now = time.time()
            key = (s.last_beacon_id, s.delta_us[s.last_beacon_id])
            with lock:
                t = sent.pop(key, None)
            if t is not None:
                latencies.append(now - t)
                read_latencies.append(s.header.stamp.to_sec() - t)

        rospy.Subscriber('/diagnostics', DiagnosticArray, on_diag, queue_size=100)
        rospy.Subscriber('/sim/beacons/sent', Float64MultiArray, on_sent, queue_size=1000)
        rospy.Subscriber('/hcl/beacons/state', BeaconReceiverState, on_state, queue_size=1000)
        time.sleep(3.0)  # boards up, meters filled
        with lock:
            del latencies[:], read_latencies[:]
        time.sleep(MEASURE_S)
        with lock:
            snapshot = dict(diag)
            lat, rlat = list(latencies), list(read_latencies)
        print('Logion I2C boards on one emulated bus (loop i2c-1), %.0f s:' % MEASURE_S)
        print('  %-20s %-9s %10s %10s %8s %12s' % ('board', 'type', 'config Hz', 'achieved', 'ratio', 'max svc ms'))
        total_cfg = total_got = 0.0
        for name in sorted(hcl):
            if name == 'beacons':
                continue
            st = [s for n, s in snapshot.items() if n.endswith('hcl/%s: board' % name)]
            kv = {v.key: v.value for v in st[0].values} if st else {}
            got = float(kv.get('achieved rate [Hz]', 'nan'))
            conf = float(hcl[name]['rate'])
            total_cfg += conf
            total_got += got
            print('  %-20s %-9s %10.1f %10.1f %7.0f%% %12s' % (name, hcl[name]['type'], conf, got, 100 * got / conf,
                                                               kv.get('max service time [ms]', '?')))
        print('  %-20s %-9s %10.1f %10.1f %7.0f%%' % ('all (sum)', '', total_cfg, total_got, 100 * total_got / total_cfg))
        print('Beacon receiver on a pty, 100 messages/s, %d messages:' % len(lat))
        print('  last byte on the pty -> /hcl/beacons/state at a subscriber: p50 %.3f ms  p99 %.3f ms  max %.3f ms'
              % (1e3 * percentile(lat, 50), 1e3 * percentile(lat, 99), 1e3 * (max(lat) if lat else float('nan'))))
        print('  last byte on the pty -> driver receive stamp:               p50 %.3f ms  p99 %.3f ms'
              % (1e3 * percentile(rlat, 50), 1e3 * percentile(rlat, 99)))
        rospy.signal_shutdown('done')
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in reversed(procs):
            try:
                p.wait(10)
            except subprocess.TimeoutExpired:
                p.kill()


if __name__ == '__main__':
    main()
