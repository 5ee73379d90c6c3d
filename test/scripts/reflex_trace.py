"""Follows a ranger reading through every hop of the simulated 2009 robot, from the CAN frame
that carries it to the CAN frame that stops the motors, for scripts/bench/latency_bench.py and
the reflex_latency rostest.

Reflex (the brain's opponent_ahead trigger): drive the robot forward on /hal/drive/cmd_vel, put
the opponent in front of it inside the trigger's distance and stop driving; the hops are
    servo board ranger PDO on the bus -> HCL /hcl/servo_board/range/<front>
    -> HAL /hal/rangers/<front> -> brain: zero on /hal/drive/cmd_vel
    -> HAL drive: zero on /hcl/motor_board/motor/left/command -> motor board command frame (PWM 0).
Avoidance (the driver alone, the brain's trigger out of reach): a driver goto, the opponent
put ahead within the driver's braking reach; from the PDO of the reading the driver acted on (the
last front reading before its first braking command: the first reading under the detection
distance may still leave the obstacle off the route) to the motor board frame carrying the
drive's wheel command for it (the driver brakes on a ramp: the decision, not the stop).
Pose age: how old /mcl/pose is when it arrives (ROS time at arrival - its stamp); and how long
after the odometry it includes (/odom of the same stamp) it arrives, for /mcl/pose and for the
tf map -> odom (stamped that odometry's stamp + the transform tolerance).

Times are wall-clock receive times: can_dump's for the frames (the kernel's, end to end), subscriptions
(no Nagle) in this process for the topics in between (they carry this process's own delays).
No extra topic is published by the product. The opponent is placed with the simulator's
/sim/place_opponent, a test tool's privilege."""
import math
import struct
import subprocess
import threading
import time

import actionlib
import rospy
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PoseWithCovarianceStamped, Pose2D, Twist
from hal_nodes.msg import GotoAction, GotoGoal
from hcl_drivers.msg import MotorCommand
from nav_msgs.msg import Odometry
from robot_sim.srv import PlaceOpponent
from sensor_msgs.msg import Range
from tf2_msgs.msg import TFMessage

FRONT = ['sharp_front_left', 'sharp_front_right']


class CanSniffer(object):
    """The bus as hcl_drivers' can_dump sees it (a participant of the CAN-over-UDP bus, stamping
    each frame with the wall clock as it arrives, in C++: this Python process's own scheduling
    does not enter the figures). Keeps (wall time, id, data) of the data frames with the given ids."""

    def __init__(self, bus, ids):
        self.ids = set(ids)
        self.frames = []
        self.lock = threading.Lock()
        exe = subprocess.check_output(['catkin_find', '--first-only', 'hcl_drivers', 'can_dump']).decode().strip()
        self.proc = subprocess.Popen([exe, bus], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        for line in self.proc.stdout:
            # (1795650000.123456) udp://127.0.0.1:27098 18C#0102030405060708
            try:
                stamp, _, frame = line.decode().split()
                cid, data = frame.split('#')
                if data.startswith('R'):
                    continue
                cid = int(cid, 16)
                if cid in self.ids:
                    with self.lock:
                        self.frames.append((float(stamp[1:-1]), cid, bytes.fromhex(data)))
            except ValueError:
                continue

    def close(self):
        self.proc.terminate()

    def last_before(self, cid, t):
        with self.lock:
            hits = [f for f in self.frames if f[1] == cid and f[0] <= t]
        return hits[-1] if hits else None

    def first_after(self, cid, t, pred):
        with self.lock:
            for f in self.frames:
                if f[1] == cid and f[0] >= t and pred(f[2]):
                    return f
        return None


class Log(object):
    """Wall receive times of a topic's messages."""

    def __init__(self, topic, cls):
        self.items = []
        self.lock = threading.Lock()
        rospy.Subscriber(topic, cls, self._cb, queue_size=50, tcp_nodelay=True)

    def _cb(self, m):
        t = time.time()
        with self.lock:
            self.items.append((t, m))

    def first_after(self, t, pred=lambda m: True):
        with self.lock:
            for ti, m in self.items:
                if ti >= t and pred(m):
                    return ti, m
        return None

    def last_before(self, t, pred=lambda m: True):
        with self.lock:
            hits = [(ti, m) for ti, m in self.items if ti <= t and pred(m)]
        return hits[-1] if hits else None


class ReflexBench(object):
    """The whole simulated 2009 robot seen from outside: plays the strategy and follows readings."""
    def __init__(self):
        bus = rospy.get_param('/hcl/motor_board/bus')
        self.motor_cob = int(rospy.get_param('/hcl/motor_board/command_cob_id', 0x200 + rospy.get_param('/hcl/motor_board/node_id')))
        self.ranger_cob = int(rospy.get_param('/hcl/servo_board/ranger_cob_id', 0x180 + rospy.get_param('/hcl/servo_board/node_id')))
        self.trigger_distance = rospy.get_param('/brain/triggers/opponent_ahead/distance')
        # The trigger fires again only once the opponent has been gone clear_time and then
        # holdoff has passed since its handler ended.
        self.rearm = (float(rospy.get_param('/brain/triggers/opponent_ahead/clear_time'))
                      + float(rospy.get_param('/brain/triggers/opponent_ahead/holdoff')))
        self.detection = rospy.get_param('/hal/driver/avoidance/detection_distance')
        self.max_accel = rospy.get_param('/hal/driver/limits/max_linear_accel')
        self.robot_radius = rospy.get_param('/robot/radius')
        self.opponent_radius = rospy.get_param('/sim/world/opponent/radius')
        self.sniffer = CanSniffer(bus, [self.motor_cob, self.ranger_cob])
        self.hcl = {n: Log('/hcl/servo_board/range/' + n, Range) for n in FRONT}
        self.hal = {n: Log('/hal/rangers/' + n, Range) for n in FRONT}
        self.cmd_vel = Log('/hal/drive/cmd_vel', Twist)
        self.motor_cmd = Log('/hcl/motor_board/motor/left/command', MotorCommand)
        self.pose_ages = []
        self.odom_arrivals = {}  # /odom stamp -> wall receive time
        self.pose_after_odom = []
        self.tf_after_odom = []
        self.tf_tolerance = rospy.get_param('/hal/localization/transform_tolerance', 0.1)
        rospy.Subscriber('/odom', Odometry, self._odom, queue_size=50, tcp_nodelay=True)
        rospy.Subscriber('/mcl/pose', PoseWithCovarianceStamped, self._pose, queue_size=50, tcp_nodelay=True)
        rospy.Subscriber('/tf', TFMessage, self._tf, queue_size=200, tcp_nodelay=True)
        self.truth = None
        rospy.Subscriber('/sim/ground_truth', Odometry, self._truth, queue_size=1)
        self.refresh_ms = {}
        rospy.Subscriber('/diagnostics', DiagnosticArray, self._diagnostics, queue_size=50)
        self.drive = rospy.Publisher('/hal/drive/cmd_vel', Twist, queue_size=1)
        rospy.wait_for_service('/sim/place_opponent', 60.0)
        self.place_srv = rospy.ServiceProxy('/sim/place_opponent', PlaceOpponent)
        self.goto = actionlib.SimpleActionClient('/hal/driver/goto', GotoAction)

    def _odom(self, m):
        self.odom_arrivals[m.header.stamp.to_nsec()] = time.time()
        if len(self.odom_arrivals) > 2000:
            for k in sorted(self.odom_arrivals)[:1000]:
                del self.odom_arrivals[k]

    def _after_odom(self, stamp_ns, out):
        t = self.odom_arrivals.get(stamp_ns)
        if t is not None:
            out.append(time.time() - t)

    def _pose(self, m):
        self.pose_ages.append((rospy.Time.now() - m.header.stamp).to_sec())
        self._after_odom(m.header.stamp.to_nsec(), self.pose_after_odom)

    def _tf(self, m):
        for t in m.transforms:
            if t.child_frame_id == 'odom':
                self._after_odom((t.header.stamp - rospy.Duration(self.tf_tolerance)).to_nsec(), self.tf_after_odom)

    def _diagnostics(self, m):
        for st in m.status:
            for kv in st.values:
                if kv.key in ('mean refresh time [ms]', 'woken refreshes', 'wakes deferred to the rate limit') or kv.key.startswith('debug'):
                    self.refresh_ms.setdefault(st.hardware_id, {})[kv.key] = kv.value

    def _truth(self, m):
        self.truth = m

    def robot(self):
        p = self.truth.pose.pose
        return p.position.x, p.position.y, 2 * math.atan2(p.orientation.z, p.orientation.w)

    def park(self):
        self.place_srv(Pose2D(2.75, 1.8, math.pi), True)

    def put_ahead(self, sensor_distance):
        x, y, yaw = self.robot()
        d = self.robot_radius + sensor_distance + self.opponent_radius
        self.place_srv(Pose2D(x + d * math.cos(yaw), y + d * math.sin(yaw), yaw + math.pi), True)

    def pwm_zero(self, data):
        return len(data) >= 4 and data[:4] == b'\x00\x00\x00\x00'

    def drive_for(self, v, seconds):
        end = time.time() + seconds
        while time.time() < end and not rospy.is_shutdown():
            t = Twist()
            t.linear.x = v
            self.drive.publish(t)
            time.sleep(0.02)

    def trace_from(self, t_place, threshold):
        """The reflex's hops of the first front reading under `threshold` after t_place, to the
        first motor board frame with PWM 0; None if missing."""
        firsts = [self.hcl[n].first_after(t_place, lambda m: m.range < threshold) for n in FRONT]
        firsts = [f for f in firsts if f]
        if not firsts:
            return None
        t_hcl, reading = min(firsts, key=lambda f: f[0])
        pdo = self.sniffer.last_before(self.ranger_cob, t_hcl)
        if not pdo:
            return None
        stop = self.sniffer.first_after(self.motor_cob, pdo[0], self.pwm_zero)
        if not stop:
            return None
        hal = [self.hal[n].first_after(t_hcl, lambda m: m.range < threshold) for n in FRONT]
        hal = [h for h in hal if h]
        t_hal = min(h[0] for h in hal) if hal else None
        brain = self.cmd_vel.first_after(t_hcl, lambda m: m.linear.x == 0.0 and m.angular.z == 0.0)
        cmd = self.motor_cmd.first_after(brain[0] if brain else t_hcl, lambda m: m.value == 0)
        return {'pdo': pdo[0], 'hcl': t_hcl, 'hal': t_hal, 'brain': brain[0] if brain else None,
                'command': cmd[0] if cmd else None, 'bus': stop[0]}

    def braking_trace(self, t_place, threshold):
        """The driver's avoidance: its first braking command after t_place (the speed falls by at
        least half the deceleration limit over the time since the command before: steering
        jitter is not braking; receive times stand for the driver's ROS time: real-time factor
        1), the front reading it acted on (the last one under `threshold`
        before it), and back to that reading's frame; forward to the drive's wheel command and
        the motor board frame that carries it. None if missing."""
        with self.cmd_vel.lock:
            cmds = [(t, m) for t, m in self.cmd_vel.items if t >= t_place - 0.1]
        brain = None
        for (t0, m0), (t1, m1) in zip(cmds, cmds[1:]):
            if t1 >= t_place and m0.linear.x - m1.linear.x >= 0.5 * self.max_accel * (t1 - t0):
                brain = t1
                break
        if brain is None:
            return None
        acted = [self.hal[n].last_before(brain, lambda m: m.range < threshold) for n in FRONT]
        acted = [a for a in acted if a and a[0] >= t_place]
        if not acted:
            return None
        t_hal, reading = max(acted, key=lambda a: a[0])
        # The HCL message of the same board exchange (same stamp; it may reach this process
        # after the HAL's, on another connection), and the frame that carried it.
        hcl = [self.hcl[n].first_after(t_place, lambda m: m.header.stamp == reading.header.stamp) for n in FRONT]
        hcl = [h for h in hcl if h]
        if not hcl:
            return None
        t_hcl = min(h[0] for h in hcl)
        pdo = self.sniffer.last_before(self.ranger_cob, t_hcl)
        # The drive's first wheel command lower than before the braking command.
        before = self.motor_cmd.last_before(brain)
        cmd = self.motor_cmd.first_after(brain, lambda m: before is not None and abs(m.value) < abs(before[1].value))
        if not pdo or not cmd:
            return None
        # The frame carrying it: the first with that left PWM after the reading's frame (not
        # after this process received the command: the frame may have gone out before that).
        left = cmd[1].value
        stop = self.sniffer.first_after(self.motor_cob, pdo[0], lambda d: struct.unpack_from('<h', d, 0)[0] == left)
        if not stop:
            return None
        return {'pdo': pdo[0], 'hcl': t_hcl, 'hal': t_hal, 'brain': brain, 'command': cmd[0], 'bus': stop[0]}

    def reflex_events(self, n):
        """n stops by the brain's opponent_ahead trigger (each traced), or fewer if some fail."""
        out = []
        self.park()
        time.sleep(0.6)
        for i in range(n * 2):
            if len(out) >= n or rospy.is_shutdown():
                break
            self.drive_for(0.25, 0.35)           # moving forward: non-zero PWM on the bus
            t_place = time.time()
            self.put_ahead(0.6 * self.trigger_distance)
            time.sleep(0.3)                      # the brain stops the wheels (the drive would hold the last command 0.3 s)
            tr = self.trace_from(t_place, self.trigger_distance)
            if tr:
                out.append(tr)
            self.park()                          # gone: the trigger clears (clear_time), the brain resumes its idle state
            t_gone = time.time()
            self.drive_for(-0.25, 0.35)          # back where it was (the rear rangers see nothing)
            self.drive.publish(Twist())
            # the trigger has re-armed (clear_time, then holdoff) before the next placement
            time.sleep(max(1.0, self.rearm + 0.2 - (time.time() - t_gone)))
        return out

    def avoidance_events(self, n):
        out = []
        if not self.goto.wait_for_server(rospy.Duration(20.0)):
            return out
        for i in range(n * 2):
            if len(out) >= n or rospy.is_shutdown():
                break
            self.park()
            time.sleep(1.2)
            x, y, yaw = self.robot()
            g = GotoGoal(x=x + 0.6 * math.cos(yaw), y=y + 0.6 * math.sin(yaw), angle=yaw, timeout=8.0)
            self.goto.send_goal(g)
            time.sleep(0.8)                      # under way, at cruise speed
            t_place = time.time()
            self.put_ahead(0.6 * self.trigger_distance)  # within the driver's braking reach: it brakes at once
            time.sleep(0.5)
            tr = self.braking_trace(t_place, self.detection)
            if tr:
                out.append(tr)
            self.goto.cancel_all_goals()
            self.park()
            time.sleep(1.0)
            back = GotoGoal(x=x, y=y, angle=yaw, allow_reverse=True, timeout=5.0)
            self.goto.send_goal_and_wait(back, rospy.Duration(6.0))
        return out
