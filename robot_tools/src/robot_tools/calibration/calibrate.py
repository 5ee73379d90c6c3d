"""`make calibrate ROBOT=... BAG=...`: the robot and the simulator's model of it, fitted to one
recorded match, from the bag alone (a match on the table records the same topics, without the
simulator's ground truth; the localization's beacon-based estimate is the reference).

    scripts/calibrate.py ROBOT BAG [--out DIR] [--report PREFIX]

Fits (robot_tools.calibration): the driven wheels' ticks per metre (left, right) and the track
width that make the odometry agree with the estimate; per drive motor the wheel speed at full PWM,
the time constant and the dead band; how much the wheels slip with their acceleration; each
ranger's bias and noise against the table's borders at the estimated pose; the beacons' range
noise. Writes DIR/ROBOT.calibrated.yaml and DIR/ROBOT.calibrated.sim.yaml (default DIR: config/;
robot_tools.calibration.output), a report PREFIX.txt and PREFIX.png beside the bag (each value with
its uncertainty beside the config's, the fits' residuals), and last
    calibrate ROBOT: P parameters, fit_rmse_wheel_speed S m/s, odometry_drift_after D mm/m (before B mm/m)
A bag without a topic it needs is refused with the list of what is missing (exit 2).
"""
import argparse
import math
import os
import sys

import numpy as np

from robot_tools.paths import ROOT
# (geometry and slip as modules: this file has its own fit_geometry and fit_slip, which call theirs)
from robot_tools.calibration import geometry as geometry_fit
from robot_tools.calibration import slip as slip_fit
from robot_tools.calibration.geometry import Segments, odometry_drift, stop_to_stop
from robot_tools.calibration.geometry_beacons import SHARED, BeaconChunks, beacon_drift, fit_geometry_beacons
from robot_tools.calibration.motor import fit_motor, wheel_speed
from robot_tools.calibration.range_errors import fit_errors, noise_with_range
from robot_tools.calibration.stats import Fit
from robot_tools.calibration import output as out
from robot_tools.calibration import replay
from robot_tools.calibration import signals as sig
from robot_tools.matches.match_config import merged, robot_config
from robot_core.config_tree import simulated_robot
from robot_core.params import ParameterError
from robot_core.robot_geometry import RobotGeometry

SEGMENT = 1.0  # [s] of the estimate per segment when the match has too few stops
MIN_SEGMENTS = 10
RANGE_USED = 0.8  # of a ranger's max_range: the readings the noise fit uses
STRETCH = 45  # [s] of dead reckoning against the beacons, at least: long, for the few start poses it
#             costs; short enough that a contact spoils a part of the match, not all of it
SIM_TICKS_PER_REV = 512.0  # a driven wheel's encoder when the description gives none (robot_sim's parseRobot)


def get(d, *path, default=None):
    for k in path:
        if not isinstance(d, dict) or k not in d:
            return default
        d = d[k]
    return d


def described(config):
    """The robot's description (RobotGeometry), as the devices read it; a bad value ends calibrate, in one line."""
    try:
        return RobotGeometry.of_config(config)
    except ParameterError as e:
        sys.exit('calibrate: %s' % e)


def ticks_per_rev(config):
    """The driven wheels' encoders' ticks per revolution: the description's, else the simulator's."""
    ticks = described(config).encoder_ticks_per_rev
    return SIM_TICKS_PER_REV if ticks is None else ticks


def odometry_track(config, driven):
    """The track the odometry integrates with (odometry_device.cpp): the driven pair's own where it
    sets one, else the description's; neither is refused, as the odometry refuses it."""
    if 'track_width' in driven:
        return float(driven['track_width'])
    track = described(config).track_width
    if track is None:
        sys.exit("calibrate: parameter /hal/odometry/pairs/driven/track_width: not set, and the robot's description "
                 "has no /robot/track_width")
    return track


def common_ticks(encoders):
    """(t, left ticks, right ticks) on the left counter's stamps."""
    tl, cl = encoders['left']
    tr, cr = encoders['right']
    return tl, cl, np.interp(tl, tr, cr)


def sim_motor(config, side):
    for name, m in (get(config, 'sim', 'world', 'robot', 'motors', default={}) or {}).items():
        if isinstance(m, dict) and m.get('drive') == side:
            return name, m
    return None, {}


def fit_geometry(s, config):
    """Against the beacons when the robot has them (geometry_beacons.BeaconChunks: the
    wheels dead-reckoned stretch by stretch against every range, independent of the odometry);
    else stop to stop against the localization's estimate, or one second at a time when the
    match has too few stops."""
    driven = get(config, 'hal', 'odometry', 'pairs', 'driven', default={})
    tpm = (float(driven['left_ticks_per_meter']), float(driven['right_ticks_per_meter']))
    track = odometry_track(config, driven)
    t, tl, tr = common_ticks(s.encoders)
    e = s.estimate
    beacons = get(config, 'table', 'beacons', default=[])
    if len(s.beacons) and beacons:
        def start_at(when):
            x, y, a = sig.pose_at(e, np.array([when]))
            return x[0], y[0], a[0]
        mx, my, _ = s.mounts['beacon receiver']
        chunks = BeaconChunks(t, tl, tr, s.beacons, beacons, (mx, my), start_at, length=STRETCH)
        if chunks.count:
            fits, kept, rms, q = fit_geometry_beacons(chunks, tpm[0], tpm[1], track)
            before = beacon_drift(chunks, tpm[0], tpm[1], track, kept=kept)
            after = beacon_drift(chunks, fits[0].value, fits[1].value, fits[2].value, kept=kept)
            # the poses the fit found (the wheels dead-reckoned with the fitted values from each
            # stretch's fitted start): the reference for the rangers, surer than the estimate of a
            # robot whose odometry was off
            reference = np.concatenate([np.column_stack(chunks.poses(k, *q[:3], q[SHARED + 3 * k:SHARED + 3 * k + 3]))
                                        for k in range(chunks.count) if kept[k]])
            spans = [c['span'] for k, c in enumerate(chunks.chunks) if kept[k]]
            return dict(tpm=tpm, track=track, fits=fits, mask=kept, rms=rms, chunks=chunks, q=q, reference=reference,
                        spans=spans,
                        kind='against the beacons, %d s stretches' % STRETCH, before=before, after=after,
                        drift_what='the beacons (RMS range residual per metre)')
    segs, kind = stop_to_stop(t, tl, tr, e[:, 0], e[:, 1], e[:, 2], e[:, 3]), 'stop to stop'
    if segs.count < MIN_SEGMENTS:
        segs, kind = Segments(t, tl, tr, e[:, 0], e[:, 1], e[:, 2], e[:, 3], length=SEGMENT), 'one second each'
    if segs.count < MIN_SEGMENTS:
        sys.exit('calibrate: only %d segments where the robot moved with a sound estimate: record a longer match'
                 % segs.count)
    fits, mask, rms = geometry_fit.fit_geometry(segs, tpm_l=tpm[0], tpm_r=tpm[1], track=track)
    before = odometry_drift(segs, tpm[0], tpm[1], track, mask)
    after = odometry_drift(segs, fits[0].value, fits[1].value, fits[2].value, mask)
    return dict(tpm=tpm, track=track, fits=fits, mask=mask, rms=rms, segs=segs, kind=kind + ' against the estimate',
                reference=e, spans=[(e[0, 0], e[-1, 0])],
                before=before, after=after, drift_what='the estimate')


def fit_motors(s, config):
    tpr = ticks_per_rev(config)
    out_ = {}
    for side in ('left', 'right'):
        if side not in s.commands or side not in s.encoders:
            continue
        t_w, w = wheel_speed(*s.encoders[side], tpr)
        name, m = sim_motor(config, side)
        guess = float(m.get('max_speed', 20.0))
        t_c, u = s.commands[side]
        # the current limiter is the config's (stall and limit currents are not fitted)
        limit = float(m.get('current_limit', 4.0)) / float(m.get('stall_current', 6.0))
        fits, rms = fit_motor(t_c, u, t_w, w, guess_speed=guess, max_accel=float(m.get('max_accel', 60.0)), limit=limit)
        out_[side] = dict(name=name, config=m, fits=fits, rms=rms, t=t_w, w=w)
    return out_


def fit_slip(geometry, s, config):
    """Slip against acceleration, one second at a time (stop to stop, slip cancels out)."""
    fl, fr, _ = geometry['fits']
    t, tl, tr = common_ticks(s.encoders)
    e = s.estimate
    segs = Segments(t, tl, tr, e[:, 0], e[:, 1], e[:, 2], e[:, 3], length=SEGMENT)
    if segs.count < 3:
        return Fit(0.0), Fit(0.0), 0.0
    odo = np.array([np.sum((segs.dl[segs.seg == k] / fl.value + segs.dr[segs.seg == k] / fr.value) / 2.0)
                    for k in range(segs.count)])
    tpr = ticks_per_rev(config)
    radius = tpr / (2 * math.pi * (fl.value + fr.value) / 2.0)
    t_w, w = wheel_speed(*s.encoders['left'], tpr)
    acc_t = 0.5 * (t_w[1:] + t_w[:-1])
    acc = np.abs(np.diff(w) / np.maximum(np.diff(t_w), 1e-3)) * radius
    seg_acc = np.array([np.mean(acc[(acc_t >= a) & (acc_t < a + SEGMENT)]) if np.any((acc_t >= a) & (acc_t < a + SEGMENT))
                        else 0.0 for a in segs.start])
    return slip_fit.fit_slip(np.abs(odo), segs.travel(), seg_acc)


def resolved(fit):
    """A fit the data pins down: its uncertainty under a third of its value."""
    return fit.sigma is not None and abs(fit.value) > 3.0 * fit.sigma


def replay_check(s, config, sim_pairs, motors):
    """{side: (error with the config's model, error with the fitted one, windows kept, left out)}."""
    binary = replay.motor_replay_binary()
    if binary is None:
        return None
    fitted = merged(config, out.nested(sim_pairs))
    encoders = simulated_robot(config).get('encoders') or {}
    result = {}
    for side, m in motors.items():
        tpr = next((float(e.get('ticks_per_rev', 512)) for e in encoders.values()
                    if isinstance(e, dict) and e.get('motor') == m['name']), None)
        if not m['name'] or tpr is None:
            continue
        before = replay.replay_error(binary, config, m['name'], tpr, s.commands[side], s.encoders[side])
        after = replay.replay_error(binary, fitted, m['name'], tpr, s.commands[side], s.encoders[side])
        result[side] = (before[0], after[0], after[1], after[2])
    return result


def fit_rangers(s, config, reference, spans):
    from robot_core.table_geometry import TableGeometry
    table = TableGeometry(float(get(config, 'table', 'length', default=3.0)), float(get(config, 'table', 'width', default=2.1)))
    out_ = {}
    for name, rows in s.rangers.items():
        mnt = s.mounts.get(name)
        if mnt is None or len(reference) < 2:
            continue
        ok = np.isfinite(rows[:, 1]) & (rows[:, 1] < rows[:, 3]) & \
            np.any([(rows[:, 0] >= a) & (rows[:, 0] <= b) for a, b in spans], axis=0)
        r = rows[ok]
        x, y, a = sig.pose_at(reference, r[:, 0])
        sx = x + np.cos(a) * mnt[0] - np.sin(a) * mnt[1]
        sy = y + np.sin(a) * mnt[0] + np.cos(a) * mnt[1]
        expected = np.array([table.cone_range(px, py, pa + mnt[2], fov) for px, py, pa, fov in zip(sx, sy, a, r[:, 4])])
        # well inside the range: near its end only the readings that came out short stay in
        keep = expected < RANGE_USED * r[:, 3]
        bias, noise, n = fit_errors(r[keep, 1], expected[keep], outlier=0.3)
        rel = noise_with_range(r[keep, 1] - expected[keep], expected[keep], bias.value)
        out_[name] = dict(bias=bias, noise=noise, rel=rel, n=n, expected=expected[keep], measured=r[keep, 1])
    return out_


def fit_beacons(s, config, geometry):
    """The beacons' range bias and noise: against the fitted dead reckoning when the geometry was
    fitted to them (the estimate of a robot whose odometry is off is off too), else against the
    estimate."""
    beacons = get(config, 'table', 'beacons', default=[])
    if len(s.beacons) == 0 or not beacons or len(s.estimate) < 2:
        return None
    if 'chunks' in geometry:
        chunks, q = geometry['chunks'], geometry['q']
        residual = np.concatenate([c['range'] - chunks.predicted(k, *q[:3], q[SHARED + 3 * k:SHARED + 3 * k + 3],
                                                                 *q[3:SHARED])
                                   for k, c in enumerate(chunks.chunks) if geometry['mask'][k]])
        bias, noise, n = fit_errors(residual, np.zeros(len(residual)), outlier=0.2)
        return dict(bias=bias, noise=noise, n=n)
    b = s.beacons[(s.beacons[:, 0] >= s.estimate[0, 0]) & (s.beacons[:, 0] <= s.estimate[-1, 0])]
    x, y, a = sig.pose_at(s.estimate, b[:, 0])
    mx, my, _ = s.mounts['beacon receiver']
    rx, ry = x + np.cos(a) * mx - np.sin(a) * my, y + np.sin(a) * mx + np.cos(a) * my
    pos = np.array([beacons[int(i)] for i in b[:, 1]], dtype=float)
    expected = np.hypot(pos[:, 0] - rx, pos[:, 1] - ry)
    bias, noise, n = fit_errors(b[:, 2], expected, outlier=0.2)
    return dict(bias=bias, noise=noise, n=n)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('robot')
    ap.add_argument('bag')
    ap.add_argument('--out', default=os.path.join(ROOT, 'config'), help='where the two overlays go (default config/)')
    ap.add_argument('--report', default=None, help='report path prefix (default: beside the bag, ROBOT_calibration)')
    args = ap.parse_args()
    path = os.path.join(ROOT, 'config', args.robot + '.yaml')
    if not os.path.exists(path):
        sys.exit('calibrate: ROBOT=%s: no config/%s.yaml' % (args.robot, args.robot))
    if not os.path.isfile(args.bag):
        sys.exit('calibrate: BAG=%s: no such file' % args.bag)
    config = robot_config(args.robot)
    import rosbag
    with rosbag.Bag(args.bag) as bag:
        topics = bag.get_type_and_topic_info().topics
        lacking = sig.missing(topics, config)
        if lacking:
            print('calibrate: %s lacks what the fit needs:' % args.bag)
            for t, why in lacking:
                print('  %s (%s)' % (t, why))
            return 2
        s = sig.read(bag, config)
    geometry = fit_geometry(s, config)
    fl, fr, fb = geometry['fits']
    tpr = ticks_per_rev(config)
    radius_l, radius_r = tpr / (2 * math.pi * fl.value), tpr / (2 * math.pi * fr.value)
    radius = 0.5 * (radius_l + radius_r)
    motors = fit_motors(s, config)
    slip = fit_slip(geometry, s, config)
    rangers = fit_rangers(s, config, geometry['reference'], geometry['spans'])
    beacons = fit_beacons(s, config, geometry)
    speed_of_sound = float(get(config, 'sim', 'world', 'beacons', 'speed_of_sound', default=343.0))

    # ---- the overlays
    with open(path) as f:
        text = f.read()
    robot_pairs = [(('hal', 'odometry', 'pairs', 'driven', 'left_ticks_per_meter'), round(fl.value, 3)),
                   (('hal', 'odometry', 'pairs', 'driven', 'right_ticks_per_meter'), round(fr.value, 3)),
                   (('robot', 'wheel_radius'), round(radius, 6))]
    robot_pairs += [(p, round(fb.value, 5)) for p in out.alias_paths(text, ('robot', 'track_width'))]
    for side, m in motors.items():
        wheel = get(config, 'hal', 'drive', 'wheels', side, default={})
        if wheel.get('units_per_mps'):
            r_side = radius_l if side == 'left' else radius_r
            robot_pairs.append((('hal', 'drive', 'wheels', side, 'units_per_mps'),
                                round(abs(float(wheel.get('max_value', 1000))) / (m['fits'][0].value * r_side), 2)))
    sim_pairs = [(('sim', 'world', 'robot', 'wheel_radius'), round(radius, 6)),
                 (('sim', 'world', 'robot', 'wheel_base'), round(fb.value, 5))]
    if resolved(slip[0]) and slip[0].value > 0:  # else the config's slip stays: the estimate cannot tell
        sim_pairs += [(('sim', 'world', 'robot', 'slip', 'per_accel'), round(slip[0].value, 5)),
                      (('sim', 'world', 'robot', 'slip', 'noise_std'), round(slip[1].value, 5))]
    for side, m in motors.items():
        if m['name']:
            for key, fit in zip(('max_speed', 'time_constant', 'dead_band'), m['fits']):
                sim_pairs.append((('sim', 'world', 'robot', 'motors', m['name'], key), round(fit.value, 5)))
    sim_rangers = get(config, 'sim', 'world', 'robot', 'rangers', default={}) or {}
    for name, r in rangers.items():
        if name in sim_rangers and r['n'] >= 20:
            sim_pairs += [(('sim', 'world', 'robot', 'rangers', name, 'bias'), round(r['bias'].value, 5)),
                          (('sim', 'world', 'robot', 'rangers', name, 'noise_std'), round(r['rel'][0], 5)),
                          (('sim', 'world', 'robot', 'rangers', name, 'noise_rel'), round(r['rel'][1], 5))]
    if beacons is not None and beacons['n'] >= 20:
        sim_pairs.append((('sim', 'world', 'beacons', 'noise_std'), float('%.4g' % (beacons['noise'].value / speed_of_sound))))
    replayed = replay_check(s, config, sim_pairs, motors)
    os.makedirs(args.out, exist_ok=True)
    robot_yaml = os.path.join(args.out, args.robot + '.calibrated.yaml')
    sim_yaml = os.path.join(args.out, args.robot + '.calibrated.sim.yaml')
    source = '# make calibrate ROBOT=%s BAG=%s (scripts/calibrate.py): %s\n'
    out.write_overlay(robot_yaml, source % (args.robot, args.bag, 'over config/%s.yaml, the robot as measured' % args.robot),
                      robot_pairs)
    out.write_overlay(sim_yaml, source % (args.robot, args.bag, 'over config/%s.sim.yaml, the simulator fitted to the robot'
                                          % args.robot), sim_pairs)

    # ---- the report
    prefix = args.report or os.path.join(os.path.dirname(os.path.abspath(args.bag)), args.robot + '_calibration')
    driven = get(config, 'hal', 'odometry', 'pairs', 'driven', default={})
    lines = ['calibration of %s from %s: geometry from %d segments %s (%d kept)'
             % (args.robot, args.bag, len(geometry['mask']), geometry['kind'], int(geometry['mask'].sum())),
             'the robot (config/%s.yaml; overlay %s):' % (args.robot, robot_yaml),
             out.value_line('left ticks per metre', fl, driven.get('left_ticks_per_meter')),
             out.value_line('right ticks per metre', fr, driven.get('right_ticks_per_meter')),
             out.value_line('track width', fb, geometry['track'], ' m'),
             out.value_line('wheel radius (mean)', Fit(radius), described(config).wheel_radius, ' m'),
             '  odometry drift against %s: %.1f mm/m before, %.1f mm/m after' % (
                 geometry['drift_what'], geometry['before'], geometry['after']),
             'the simulator (config/%s.sim.yaml; overlay %s):' % (args.robot, sim_yaml)]
    rms_speed = []
    for side, m in motors.items():
        for key, fit in zip(('max_speed', 'time_constant', 'dead_band'), m['fits']):
            lines.append(out.value_line('motor %s %s' % (m['name'] or side, key), fit, m['config'].get(key)))
        lines.append('  motor %s: RMS wheel speed error %.2f rad/s (%.3f m/s)' % (m['name'] or side, m['rms'], m['rms'] * radius))
        rms_speed.append(m['rms'] * radius)
    sim_slip = get(config, 'sim', 'world', 'robot', 'slip', default={}) or {}
    lines += [out.value_line('slip per_accel', slip[0], sim_slip.get('per_accel'), ' /(m/s^2)'),
              out.value_line('slip noise_std', slip[1], sim_slip.get('noise_std')),
              '  segments slipping (beyond 3 spreads): %.1f %%%s' % (
                  100 * slip[2], '' if resolved(slip[0]) else '; slip not resolved by this match, the config\'s kept')]
    for name, r in sorted(rangers.items()):
        cfg = sim_rangers.get(name, {}) or {}
        lines += [out.value_line('ranger %s bias' % name, r['bias'], cfg.get('bias', 0.0), ' m'),
                  out.value_line('ranger %s noise (all ranges)' % name, r['noise'], None, ' m'),
                  '  %-44s %.4g m + %.4g per m (config: %s + %s) over %d readings' % (
                      'ranger %s noise_std + noise_rel' % name, r['rel'][0], r['rel'][1], cfg.get('noise_std', '-'),
                      cfg.get('noise_rel', '-'), r['n'])]
    if beacons is not None:
        cfg = get(config, 'sim', 'world', 'beacons', default={}) or {}
        lines += [out.value_line('beacon range bias', beacons['bias'], None, ' m'),
                  out.value_line('beacon range noise', beacons['noise'], None, ' m'),
                  '  %-44s %.4g s (config: %s)' % ('beacons noise_std (time of flight)', beacons['noise'].value / speed_of_sound,
                                                  cfg.get('noise_std', '-'))]
    if replayed is None:
        lines.append('the recorded commands replayed: robot_sim\'s motor_replay not built (make build)')
    for side, (before, after, kept, left_out) in sorted((replayed or {}).items()):
        lines.append('  %-44s %.2f %% of the recording (config\'s model: %.2f %%), %d s compared, %d s left out (in contact)'
                     % ('replay %s motor: encoder counts off by' % side, 100 * after, 100 * before, kept, left_out))
    n_params = len(robot_pairs) + len(sim_pairs)
    closing = 'calibrate %s: %d parameters, fit_rmse_wheel_speed %.3f m/s, odometry_drift_after %.1f mm/m (before %.1f mm/m)' % (
        args.robot, n_params, max(rms_speed) if rms_speed else float('nan'), geometry['after'], geometry['before'])
    lines.append(closing)
    if 'chunks' in geometry:
        chunks, q = geometry['chunks'], geometry['q']
        series = []
        for k, c in enumerate(chunks.chunks):
            if geometry['mask'][k]:
                start = q[SHARED + 3 * k:SHARED + 3 * k + 3]
                series.append((c['rt'], c['range'] - chunks.predicted(k, *q[:3], start, *q[3:SHARED]),
                               'stretch %d' % (k + 1)))
        panels = [('beacon ranges against the fitted dead reckoning', series, 'time [s]', 'residual [m]')]
    else:
        segs, m = geometry['segs'], geometry['mask']
        got = segs.integrate(fl.value, fr.value, fb.value)
        panels = [('odometry against the estimate per segment (%s, kept)' % geometry['kind'], [
            (segs.start[m], got[m, 0] - segs.target[m, 0], 'forward residual [m]'),
            (segs.start[m], got[m, 1] - segs.target[m, 1], 'sideways residual [m]')], 'time [s]', '[m]')]
    panels += [('motor %s: measured wheel speed' % m['name'], [(m['t'], m['w'], 'measured')], 'time [s]', '[rad/s]')
               for m in motors.values()]
    if rangers:
        panels.append(('rangers: measured against expected border range', [(r['expected'], r['measured'] - r['expected'], n)
                                                                            for n, r in sorted(rangers.items())],
                       'expected [m]', 'residual [m]'))
    with open(prefix + '.txt', 'w') as f:
        f.write('\n'.join(lines) + '\n')
    out.plot(prefix + '.png', args.robot, panels)
    print('\n'.join(lines[:-1] + ['report: %s.txt, %s.png' % (prefix, prefix), closing]), flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
