"""The estimators of make calibrate (robot_tools.calibration) on synthetic signals with a known
answer: the geometry of a robot whose wheels differ from its config, a motor's speed at full
PWM, time constant and dead band, the wheels' slip, a ranger's bias and noise."""
import math
import os
import unittest

import numpy as np

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
from robot_tools.calibration.geometry import Segments, fit_geometry, odometry_drift
from robot_tools.calibration.motor import fit_motor, simulate_motor, wheel_speed
from robot_tools.calibration.range_errors import fit_errors
from robot_tools.calibration.slip import fit_slip
from robot_tools.calibration.stats import unwrap


def drive(tpm_l, tpm_r, track, seconds=90.0, rate=100.0, seed=1):
    """A robot driving straights and turns: its true pose and its wheels' encoder counts."""
    rng = np.random.default_rng(seed)
    dt = 1.0 / rate
    t = np.arange(0.0, seconds, dt)
    v = 0.3 * (np.sin(0.21 * t) > -0.3) * (0.6 + 0.4 * np.sin(0.7 * t))
    w = 1.2 * np.sin(0.33 * t + 1.0) * (np.sin(0.21 * t) <= 0.4)
    x, y, th = np.zeros(len(t)), np.zeros(len(t)), np.zeros(len(t))
    for k in range(1, len(t)):
        th[k] = th[k - 1] + w[k - 1] * dt
        x[k] = x[k - 1] + v[k - 1] * dt * math.cos(th[k - 1] + 0.5 * w[k - 1] * dt)
        y[k] = y[k - 1] + v[k - 1] * dt * math.sin(th[k - 1] + 0.5 * w[k - 1] * dt)
    sl = np.concatenate([[0.0], np.cumsum((v - w * track / 2)[:-1] * dt)])
    sr = np.concatenate([[0.0], np.cumsum((v + w * track / 2)[:-1] * dt)])
    ticks_l, ticks_r = np.floor(sl * tpm_l), np.floor(sr * tpm_r)
    return t, ticks_l, ticks_r, x, y, th, rng


class GeometryTest(unittest.TestCase):
    def test_wheels_and_track_off_by_percents_are_found_within_0_3_percent(self):
        true_l, true_r, true_b = 2328.3 * 1.03, 2328.3 * 0.985, 0.25 * 1.03
        t, tl, tr, x, y, th, rng = drive(true_l, true_r, true_b)
        # the localization's estimate: every 20 ms, a few millimetres and a few mrad of noise
        k = np.arange(0, len(t), 2)
        ex, ey = x[k] + rng.normal(0, 0.003, len(k)), y[k] + rng.normal(0, 0.003, len(k))
        eth = th[k] + rng.normal(0, 0.006, len(k))
        segs = Segments(t, tl, tr, t[k], ex, ey, eth, length=1.0)
        (fl, fr, fb), mask, rms = fit_geometry(segs, tpm_l=2328.3, tpm_r=2328.3, track=0.25)
        self.assertLess(abs(fl.value / true_l - 1), 0.003, fl)
        self.assertLess(abs(fr.value / true_r - 1), 0.003, fr)
        self.assertLess(abs(fb.value / true_b - 1), 0.003, fb)
        self.assertGreater(mask.mean(), 0.9)
        for f, true in ((fl, true_l), (fr, true_r), (fb, true_b)):  # an uncertainty that covers the truth
            self.assertIsNotNone(f.sigma)
            self.assertLess(abs(f.value - true), 3.0 * f.sigma + 1e-12, f)
        long_segs = Segments(t, tl, tr, t[k], ex, ey, eth, length=6.0)
        before = odometry_drift(long_segs, 2328.3, 2328.3, 0.25)
        after = odometry_drift(long_segs, fl.value, fr.value, fb.value)
        self.assertLess(after, 0.5 * before, 'drift %.1f mm/m, before %.1f' % (after, before))

    def test_a_slipping_stretch_is_left_out(self):
        t, tl, tr, x, y, th, rng = drive(2328.3, 2328.3, 0.25, seed=2)
        tl = tl.copy()
        tl[3000:3300] += np.linspace(0, 400, 300)  # the left wheel spins 17 cm on the spot
        tl[3300:] += 400
        segs = Segments(t, tl, tr, t, x, y, th, length=1.0)
        (fl, fr, fb), mask, _ = fit_geometry(segs, tpm_l=2328.3, tpm_r=2328.3, track=0.25)
        self.assertLess(abs(fl.value / 2328.3 - 1), 0.003)
        self.assertLess(mask.sum(), len(mask))

    def test_counters_that_wrap_are_unwrapped(self):
        raw = np.array([65530, 65535, 3, 10, 2, 65534]) % 65536
        self.assertEqual(list(unwrap(raw, 16)), [65530, 65535, 65539, 65546, 65538, 65534])


class MotorTest(unittest.TestCase):
    def test_speed_time_constant_and_dead_band_are_found(self):
        true = dict(max_speed=24.0, time_constant=0.08, dead_band=0.05)
        t_cmd = np.arange(0.0, 30.0, 0.02)
        u = 0.6 * np.sin(0.4 * t_cmd) + 0.3 * np.sign(np.sin(1.3 * t_cmd))
        u_of_t = lambda tt: u[np.clip(np.searchsorted(t_cmd, tt, side='right') - 1, 0, len(u) - 1)]  # noqa: E731
        t_enc = np.arange(0.0, 30.0, 0.01)
        w = simulate_motor(t_enc, u_of_t, true['max_speed'], true['time_constant'], true['dead_band'])
        ticks = np.floor(np.concatenate([[0.0], np.cumsum(w[:-1] * 0.01)]) * 512 / (2 * math.pi))
        t_w, w_meas = wheel_speed(t_enc, ticks, 512)
        (speed, tau, band), rms = fit_motor(t_cmd, u, t_w, w_meas, guess_speed=28.0)
        self.assertLess(abs(speed.value / 24.0 - 1), 0.05, speed)
        self.assertLess(abs(tau.value / 0.08 - 1), 0.2, tau)
        self.assertLess(abs(band.value - 0.05), 0.02, band)
        self.assertLess(rms, 2.0)

    def test_with_the_current_limiter_and_a_wheel_held_by_a_contact(self):
        # steps from rest to full and back: the limiter (current_limit / stall_current) shapes them,
        # and for 2 s a contact holds the wheel while the command stays on
        limit = 5.0 / 8.0
        t_cmd = np.arange(0.0, 30.0, 0.02)
        u = np.where(np.sin(0.7 * t_cmd) > 0, 1.0, -0.5) * (np.sin(0.23 * t_cmd) > -0.8)
        u_of_t = lambda tt: u[np.clip(np.searchsorted(t_cmd, tt, side='right') - 1, 0, len(u) - 1)]  # noqa: E731
        t_enc = np.arange(0.0, 30.0, 0.01)
        w = simulate_motor(t_enc, u_of_t, 28.0, 0.06, 0.0, max_accel=60.0, dt=0.001, limit=limit)
        w[(t_enc > 12.0) & (t_enc < 14.0)] = 0.0
        ticks = np.floor(np.concatenate([[0.0], np.cumsum(w[:-1] * 0.01)]) * 512 / (2 * math.pi))
        t_w, w_meas = wheel_speed(t_enc, ticks, 512)
        (speed, tau, band), _ = fit_motor(t_cmd, u, t_w, w_meas, guess_speed=24.0, max_accel=60.0, limit=limit)
        self.assertLess(abs(speed.value / 28.0 - 1), 0.05, speed)
        self.assertLess(abs(tau.value / 0.06 - 1), 0.2, tau)
        self.assertLess(band.value, 0.02, band)


class ReplayTest(unittest.TestCase):
    def test_counts_error_by_window_with_contacts_left_out(self):
        from robot_tools.calibration import replay
        recorded = np.array([100.0, 200.0, -150.0, 300.0, 250.0, 180.0, 120.0, 90.0])
        self.assertAlmostEqual(replay.counts_error(recorded, -recorded)[0], 0.0)  # the encoder's sign is free
        off, kept, left_out = replay.counts_error(recorded, recorded * 1.05)
        self.assertAlmostEqual(off, 0.05, places=6)
        self.assertEqual((kept, left_out), (8, 0))
        held = recorded.copy()
        held[3] = 0.0  # the recording's wheel held by a contact in one window; the free model turned
        off, kept, left_out = replay.counts_error(held, recorded * 1.005)
        self.assertEqual(left_out, 1)
        self.assertAlmostEqual(off, 0.005, places=6)


class SlipAndRangesTest(unittest.TestCase):
    def test_slip_grows_with_acceleration(self):
        rng = np.random.default_rng(3)
        acc = rng.uniform(0.0, 1.0, 400)
        est = rng.uniform(0.2, 0.5, 400)
        odo = est * (1.0 + 0.02 * acc + rng.normal(0, 0.003, 400))
        per_accel, noise, share = fit_slip(odo, est, acc)
        self.assertAlmostEqual(per_accel.value, 0.02, delta=0.002)
        self.assertAlmostEqual(noise.value, 0.003, delta=0.0006)
        self.assertLess(share, 0.05)

    def test_a_rangers_bias_and_noise_without_the_opponents_echoes(self):
        rng = np.random.default_rng(4)
        expected = rng.uniform(0.1, 0.8, 2000)
        measured = expected + 0.012 + rng.normal(0, 0.008, 2000)
        measured[:150] = expected[:150] - rng.uniform(0.2, 0.5, 150)  # the opponent in front
        bias, noise, n = fit_errors(measured, expected)
        self.assertAlmostEqual(bias.value, 0.012, delta=0.001)
        self.assertLess(abs(noise.value / 0.008 - 1), 0.2)
        self.assertGreater(n, 1700)


if __name__ == '__main__':
    unittest.main()
