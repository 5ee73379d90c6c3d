"""Compass calibration from a recorded run: the offset between the HAL compass heading
(/hal/compass/heading, hal_nodes/Heading) and a reference yaw (nav_msgs/Odometry: the
simulator's /sim/ground_truth, or on the real table any recorded reference you trust, e.g. an
external tracker). Only readings taken while the robot does not turn count (the compass lags a turn). Prints the mean/median offset and the corrected
~north_yaw for the Compass device (compass reads yaw - offset: add the offset to north_yaw).

usage: compass_offset.py BAG [--reference /sim/ground_truth] [--north-yaw 1.5708]
Offline tool: it reads a bag, never a running simulation."""
import argparse
import math

import numpy as np
import rosbag
from robot_core.geometry import wrap_angle, yaw_of


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('bag')
    ap.add_argument('--reference', default='/sim/ground_truth')
    ap.add_argument('--compass', default='/hal/compass/heading')
    ap.add_argument('--north-yaw', type=float, default=None, help='the current ~north_yaw [rad]')
    ap.add_argument('--max-turn-rate', type=float, default=0.05, help='[rad/s] readings while turning faster are skipped')
    a = ap.parse_args()
    tt, ty, tw, hs = [], [], [], []
    with rosbag.Bag(a.bag) as b:
        for topic, m, _ in b.read_messages([a.reference, a.compass]):
            if topic == a.reference:
                tt.append(m.header.stamp.to_sec())
                ty.append(yaw_of(m.pose.pose.orientation))
                tw.append(abs(m.twist.twist.angular.z))
            else:
                hs.append((m.header.stamp.to_sec(), m.yaw))
    if len(tt) < 2 or not hs:
        raise SystemExit('no %s or no %s in %s' % (a.reference, a.compass, a.bag))
    tt, ty, tw = np.array(tt), np.unwrap(np.array(ty)), np.array(tw)
    d = []
    for t, h in hs:
        if t < tt[0] or t > tt[-1] or np.interp(t, tt, tw) > a.max_turn_rate:
            continue
        r = np.interp(t, tt, ty)
        d.append(wrap_angle(h - r))
    if not d:
        raise SystemExit('no compass reading while not turning')
    d = np.degrees(np.array(d))
    print('compass - reference yaw over %d readings (not turning): mean %.2f deg, median %.2f deg, std %.2f deg'
          % (len(d), d.mean(), np.median(d), d.std()))
    if a.north_yaw is not None:
        print('calibrated ~north_yaw: %.4f rad' % (a.north_yaw - math.radians(d.mean())))


if __name__ == '__main__':
    main()
