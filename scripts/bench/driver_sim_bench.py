#!/usr/bin/env python3
"""Driver benchmark on the whole simulated 2009 robot (scripts/bench/driver_sim.launch, started by
scripts/bench/driver.sh): 20 fixed goto goals chained across the empty table, then cancels at
random points of drives. Prints, against the simulator's ground truth (read by this bench only):
mean time to goal, final position and heading error, overshoot beyond the goal along the
approach, and the time from cancel to zero cmd_vel, to zero motor command at the HCL and to the
wheels stopped (p50/p99/max). The same 20 goals as the kinematic-model bench (driver_bench.cpp).
   driver_sim_bench.py [--cancels 20] [--seed 1]"""
import argparse
import math
import random
import sys
import time

import actionlib
import rospy
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import Twist
from hal_nodes.msg import GotoAction, GotoGoal, LocalizationQuality
from hcl_drivers.msg import MotorCommand
from nav_msgs.msg import Odometry
from robot_core.geometry import wrap_angle

from test_support import Recorder, yaw_of  # test/scripts (driver.sh puts it on PYTHONPATH)

GOALS = [(2.60, 1.70, 0.00), (0.40, 1.70, math.pi), (0.40, 0.40, -math.pi / 2), (2.60, 0.40, 0.0),
         (1.50, 1.05, math.pi / 2), (1.50, 1.60, math.pi / 2), (1.00, 1.00, 2.0), (1.02, 1.01, 2.0),
         (2.20, 0.70, -0.7), (0.70, 1.40, 2.5), (2.80, 1.05, 0.0), (2.30, 1.05, 0.0), (0.30, 0.30, -2.4),
         (1.20, 0.60, 0.3), (1.80, 1.50, 1.2), (0.60, 0.90, -3.0), (2.50, 1.80, 0.8), (1.50, 0.30, -1.5),
         (1.50, 0.35, -1.5), (0.35, 1.75, 2.8)]
DEG = math.pi / 180.0
STOPPED_SPEED = 0.005    # [m/s] truth linear speed below which the wheels count as stopped
STOPPED_TURN = 0.05      # [rad/s] and the turn rate


def percentile(values, p):
    v = sorted(values)
    return v[min(len(v) - 1, max(0, int(math.ceil(p * len(v))) - 1))]


class Bench(object):
    def __init__(self):
        self.truth = Recorder('/sim/ground_truth', Odometry)
        self.cmd = Recorder('/hal/drive/cmd_vel', Twist)
        self.motor = Recorder('/hcl/motor_board/motor/left/command', MotorCommand)
        self.quality = Recorder('/mcl/quality', LocalizationQuality)
        self.goto = actionlib.SimpleActionClient('/hal/driver/goto', GotoAction)

    def wait_ready(self):
        if not self.goto.wait_for_server(rospy.Duration(90)):
            sys.exit('driver sim bench: no /hal/driver/goto after 90 s')
        deadline = time.monotonic() + 90
        while time.monotonic() < deadline:
            q = self.quality.last()
            if q is not None and q.probability > 0.6 and self.truth.last() is not None:
                time.sleep(2.0)
                return
            time.sleep(0.2)
        sys.exit('driver sim bench: the localization did not become confident within 90 s')

    def truth_pose(self):
        m = self.truth.last()
        return m.pose.pose.position.x, m.pose.pose.position.y, yaw_of(m.pose.pose.orientation)

    def goals(self):
        times, pos, ang, over, failed = [], [], [], [], []
        own_pos, own_ang = [], []  # the driver's own final errors (its localization's view)
        for i, (gx, gy, ga) in enumerate(GOALS):
            sx, sy, _ = self.truth_pose()
            t0 = time.monotonic()
            s0 = rospy.get_rostime()
            self.goto.send_goal(GotoGoal(x=gx, y=gy, angle=ga, timeout=30.0))
            self.goto.wait_for_result(rospy.Duration(40))
            took = (rospy.get_rostime() - s0).to_sec()
            state, result = self.goto.get_state(), self.goto.get_result()
            time.sleep(0.5)  # settle: the final error is measured standing
            x, y, th = self.truth_pose()
            ux, uy = gx - sx, gy - sy
            n = math.hypot(ux, uy)
            o = max([((m.pose.pose.position.x - gx) * ux + (m.pose.pose.position.y - gy) * uy) / n
                     for _, m in self.truth.since(t0)] + [0.0]) if n > 1e-3 else 0.0
            if result is not None:
                own_pos.append(result.position_error)
                own_ang.append(abs(result.angle_error))
            if state != GoalStatus.SUCCEEDED:
                failed.append('%d (%s)' % (i + 1, result.message if result else 'no result'))
            times.append(took)
            pos.append(math.hypot(x - gx, y - gy))
            ang.append(abs(wrap_angle(th - ga)))
            over.append(o)
        print('20 goto goals (2009 robot, simulator seed %s, empty table): %d succeeded%s'
              % (rospy.get_param('/sim/seed', '?'), len(GOALS) - len(failed),
                 '' if not failed else '; failed: ' + ', '.join(failed)))
        print('  time to goal (simulated s): mean %.2f, max %.2f' % (sum(times) / len(times), max(times)))
        print('  final position error vs ground truth: mean %.1f mm, max %.1f mm'
              % (1e3 * sum(pos) / len(pos), 1e3 * max(pos)))
        print('  final heading error vs ground truth: mean %.2f deg, max %.2f deg'
              % (sum(ang) / len(ang) / DEG, max(ang) / DEG))
        if own_pos:
            print('  final error by the driver\'s own estimate: mean %.1f mm, max %.1f mm; heading mean %.2f deg, max %.2f deg '
                  '(the rest of the ground-truth error is the localization\'s)'
                  % (1e3 * sum(own_pos) / len(own_pos), 1e3 * max(own_pos), sum(own_ang) / len(own_ang) / DEG, max(own_ang) / DEG))
        print('  overshoot beyond the goal along the approach: mean %.1f mm, max %.1f mm'
              % (1e3 * sum(over) / len(over), 1e3 * max(over)))

    def cancels(self, count, rng):
        cmd_ms, motor_ms, stopped_ms = [], [], []
        far = [(0.5, 1.05, 0.0), (2.5, 1.05, 0.0)]
        for i in range(count):
            x, _, _ = self.truth_pose()
            target = far[1] if x < 1.5 else far[0]
            self.goto.send_goal(GotoGoal(x=target[0], y=target[1], angle=target[2], timeout=30.0))
            time.sleep(rng.uniform(1.0, 2.0))   # turning or driving, up to full speed
            t0 = time.monotonic()
            self.goto.cancel_goal()
            self.goto.wait_for_result(rospy.Duration(5))
            time.sleep(1.0)
            zero_cmd = [t for t, m in self.cmd.since(t0) if m.linear.x == 0.0 and m.angular.z == 0.0]
            zero_motor = [t for t, m in self.motor.since(t0) if m.value == 0]
            still = [t for t, m in self.truth.since(t0)
                     if abs(m.twist.twist.linear.x) < STOPPED_SPEED and abs(m.twist.twist.angular.z) < STOPPED_TURN]
            if zero_cmd:
                cmd_ms.append(1e3 * (zero_cmd[0] - t0))
            if zero_motor:
                motor_ms.append(1e3 * (zero_motor[0] - t0))
            if still:
                stopped_ms.append(1e3 * (still[0] - t0))
        print('%d cancels mid-drive (1-2 s after the goal):' % count)
        for name, v in [('zero cmd_vel (HAL)', cmd_ms), ('zero motor command (HCL)', motor_ms),
                        ('wheels stopped (truth < 5 mm/s, 0.05 rad/s)', stopped_ms)]:
            if len(v) < count:
                print('  %s: seen after %d of %d cancels' % (name, len(v), count))
            if v:
                print('  %s: p50 %.1f ms, p99 %.1f ms, max %.1f ms' % (name, percentile(v, 0.5), percentile(v, 0.99), max(v)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--cancels', type=int, default=20)
    ap.add_argument('--seed', type=int, default=1, help='the cancel times')
    args = ap.parse_args(rospy.myargv()[1:])
    rospy.init_node('driver_sim_bench', disable_signals=True)
    bench = Bench()
    bench.wait_ready()
    bench.goals()
    bench.cancels(args.cancels, random.Random(args.seed))


if __name__ == '__main__':
    main()
