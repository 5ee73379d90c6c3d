#!/usr/bin/env python3
"""Beacon receiver over a pty with garbage and truncated messages injected by the emulator."""
import subprocess
import sys
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from hcl_drivers.msg import BeaconDelta, BeaconReceiverState
from std_msgs.msg import Float64MultiArray, UInt32MultiArray
from test_support import Recorder, wait_for


class SerialBeaconsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_serial_beacons')
        cls.sent = Recorder('/sim/beacons/sent', Float64MultiArray, queue_size=1000)
        cls.injected = Recorder('/sim/beacons/injected', UInt32MultiArray, queue_size=1000)
        cls.delta = Recorder('/hcl/beacons/delta', BeaconDelta, queue_size=1000)
        cls.state = Recorder('/hcl/beacons/state', BeaconReceiverState, queue_size=1000)
        cls.diagnostics = Recorder('/diagnostics', DiagnosticArray, queue_size=1000)
        assert wait_for(lambda: len(cls.delta.since()) > 20, 30.0, step=0.05), 'no beacon deltas'

    def test_1_every_valid_message_comes_through_in_order(self):
        t0 = time.time()  # wall clock, as the emulator stamps data[3]
        time.sleep(4.0)
        t1 = time.time() - 0.3
        sent = [(m.data[3], int(m.data[0]), int(m.data[1])) for _, m in self.sent.since() if t0 <= m.data[3] <= t1]
        self.assertGreater(len(sent), 100)
        got = [(m.header.stamp.to_sec(), m.beacon_id, m.delta_us) for _, m in self.delta.since()]
        keys = [(i, d) for _, i, d in got]
        pos = 0
        missing = []
        for t_sent, i, d in sent:
            try:
                pos = keys.index((i, d), pos) + 1
            except ValueError:
                missing.append((i, d))
                continue
            # Stamped when the last byte arrived: after it was written, and promptly.
            stamp = got[pos - 1][0]
            self.assertGreaterEqual(stamp, t_sent - 0.001)
            self.assertLess(stamp - t_sent, 0.05)
        self.assertEqual(missing, [], '%d of %d valid messages lost' % (len(missing), len(sent)))

    def test_2_garbage_and_truncations_are_counted_not_published(self):
        inj = self.injected.last()
        self.assertIsNotNone(inj)
        garbage_injected, truncated_injected = inj.data
        self.assertGreater(garbage_injected, 0)
        self.assertGreater(truncated_injected, 0)
        s = self.state.last()
        self.assertGreater(s.garbage_bytes + s.malformed, 0)
        self.assertGreater(s.malformed, 0)  # truncated messages end malformed
        self.assertLessEqual(s.garbage_bytes, garbage_injected + 12)
        # Nothing but real beacons: ids 0..2 and the emulator's delta ranges.
        for _, m in self.delta.since():
            self.assertIn(m.beacon_id, (0, 1, 2))
            self.assertIn(m.delta_us - (3000, 4500, 6000)[m.beacon_id], range(0, 1000))
        self.assertEqual(len(s.delta_us), 3)
        self.assertTrue(s.port_open)

    def statuses(self, t0):
        out = {}
        for t, arr in self.diagnostics.since():
            if t >= t0:
                for st in arr.status:
                    out[st.name] = st
        return out

    def test_3_bad_input_is_named_with_counters(self):
        # Garbage after every 2nd message and every 5th cut short: the driver names the bad input
        # at ERROR (it stays so while it lasts, and for 1 s after) and keeps every valid message.
        t0 = time.monotonic()
        # A level that holds is said once a second (~diagnostic_period): the next one after t0.
        self.assertTrue(wait_for(lambda: any('hcl/beacons:' in n for n in self.statuses(t0)), 2.5, step=0.05))
        st = [s for n, s in self.statuses(t0).items() if 'hcl/beacons:' in n]
        self.assertEqual(st[0].level, DiagnosticStatus.ERROR, st[0].message)
        self.assertIn('bad input on', st[0].message)
        self.assertIn('garbage byte(s)', st[0].message)
        kv = {v.key: v.value for v in st[0].values}
        self.assertGreater(int(kv['garbage bytes']), 0)
        self.assertGreater(int(kv['valid messages']), 100)

    def test_9_receiver_gone_is_reported_and_nothing_crashes(self):
        subprocess.check_call(['rosnode', 'kill', '/sim/firmware'], stdout=subprocess.DEVNULL)
        killed = time.monotonic()

        def named():
            st = [s for n, s in self.statuses(killed).items() if 'hcl/beacons:' in n]
            return st and st[0].level in (DiagnosticStatus.ERROR, DiagnosticStatus.STALE)
        self.assertTrue(wait_for(named, 3.0, step=0.05), 'receiver gone not named: %s' % [
            (s.level, s.message) for n, s in self.statuses(killed).items() if 'hcl/beacons:' in n])
        out = subprocess.run(['rosnode', 'ping', '-c', '1', '/hcl'], stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        self.assertEqual(out.returncode, 0, out.stdout.decode())


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'serial_beacons', SerialBeaconsTest, sys.argv)
