"""What `make calibrate` reads of a recorded match (scripts/calibrate.py), from the bag alone: the
topics a robot records on the table as in simulation (no ground truth), named by the robot's
config.

  the reference     /mcl/pose (the localization's estimate from the beacons) and /mcl/quality
  the odometry      the driven wheels' encoder counters (hal/odometry/pairs/driven/left, right)
  the motors        the PWM each drive motor's board applied, from its state (MotorBoardState
                    pwm_applied, read in the same exchange as the encoder counters) where the
                    board reports it, else the drive's commands (hal/drive/wheels/<side>/topic,
                    value / max_value, stamped when sent)
  the rangers       the boards' raw readings (hal/rangers/rangers/<name>/topic), placed by /tf_static
  the beacons       /hal/beacons/ranges, the receiver placed by /tf_static
"""
import collections
import math

import numpy as np

Signals = collections.namedtuple('Signals', 'estimate encoders commands rangers mounts beacons')

TF_STATIC = '/tf_static'
ESTIMATE, QUALITY, BEACONS = '/mcl/pose', '/mcl/quality', '/hal/beacons/ranges'


def needed(config):
    """{topic: what it is for} of the config's robot."""
    hal = config.get('hal', {})
    driven = hal.get('odometry', {}).get('pairs', {}).get('driven', {})
    out = {ESTIMATE: "the reference: the localization's estimate", QUALITY: 'when the estimate is sound',
           TF_STATIC: "the sensors' mounts"}
    for side in ('left', 'right'):
        if driven.get(side):
            out[driven[side]] = 'the %s driven wheel\'s encoder' % side
        wheel = hal.get('drive', {}).get('wheels', {}).get(side, {})
        if wheel.get('topic'):
            out[wheel['topic']] = 'the %s motor\'s PWM commands' % side
    for name, r in (hal.get('rangers', {}).get('rangers', {}) or {}).items():
        if isinstance(r, dict) and r.get('topic'):
            out[r['topic']] = 'ranger %s\'s readings' % name
    if hal.get('beacons'):
        out[BEACONS] = "the beacons' ranges"
    return out


def missing(topics, config):
    """[(topic, what it is for)] the bag lacks."""
    return [(t, why) for t, why in sorted(needed(config).items()) if t not in topics]


def _yaw(q):
    return 2.0 * math.atan2(q.z, q.w)


def _static_transforms(bag):
    """{child frame: (parent, x, y, yaw)} of /tf_static."""
    out = {}
    for _, msg, _ in bag.read_messages(topics=[TF_STATIC]):
        for t in msg.transforms:
            tr = t.transform
            out[t.child_frame_id] = (t.header.frame_id, tr.translation.x, tr.translation.y, _yaw(tr.rotation))
    return out


def mount(transforms, frame, base='base_link'):
    """(x, y, yaw) of `frame` in `base`, composed along /tf_static; None when not connected."""
    x, y, a = 0.0, 0.0, 0.0
    seen = set()
    while frame != base:
        if frame in seen or frame not in transforms:
            return None
        seen.add(frame)
        parent, px, py, pa = transforms[frame]
        # child in parent: compose parent <- child
        x, y, a = px + math.cos(pa) * x - math.sin(pa) * y, py + math.sin(pa) * x + math.cos(pa) * y, pa + a
        frame = parent
    return x, y, a


def read(bag, config):
    """Signals of a recorded match: numpy arrays, times in seconds of the bag's clock (header stamps)."""
    hal = config.get('hal', {})
    quality = []
    for _, msg, t in bag.read_messages(topics=[QUALITY]):
        quality.append((msg.header.stamp.to_sec(), msg.probability, bool(getattr(msg, 'lost', False))))
    est = []
    for _, msg, t in bag.read_messages(topics=[ESTIMATE]):
        p = msg.pose.pose
        est.append((msg.header.stamp.to_sec(), p.position.x, p.position.y, _yaw(p.orientation)))
    est = np.array(sorted(est)) if est else np.zeros((0, 4))
    if quality and len(est):
        q = np.array(sorted(quality))
        prob = np.interp(est[:, 0], q[:, 0], q[:, 1])
        est = est[prob >= 0.6]
    driven = hal.get('odometry', {}).get('pairs', {}).get('driven', {})
    from robot_tools.calibration.stats import unwrap
    encoders = {}
    for side in ('left', 'right'):
        rows = [(m.header.stamp.to_sec(), m.raw, m.bits) for _, m, _ in bag.read_messages(topics=[driven.get(side, '')])]
        if rows:
            rows.sort()
            a = np.array(rows, dtype=float)
            encoders[side] = (a[:, 0], unwrap(a[:, 1].astype(np.int64), int(rows[0][2] or 32)).astype(float))
    commands = {}
    for side in ('left', 'right'):
        wheel = hal.get('drive', {}).get('wheels', {}).get(side, {})
        full = float(wheel.get('max_value', 1000)) or 1000.0
        rows = sorted((m.header.stamp.to_sec(), m.value / full) for _, m, _ in bag.read_messages(topics=[wheel.get('topic', '')]))
        if rows:
            a = np.array(rows)
            commands[side] = (a[:, 0], np.clip(a[:, 1], -1.0, 1.0))
    applied = _applied_pwm(bag, hal)
    commands.update(applied)
    transforms = _static_transforms(bag)
    rangers, mounts = {}, {}
    for name, r in (hal.get('rangers', {}).get('rangers', {}) or {}).items():
        rows, frame = [], r.get('frame_id')
        for _, m, _ in bag.read_messages(topics=[r.get('topic', '')]):
            rows.append((m.header.stamp.to_sec(), m.range, m.min_range, m.max_range, m.field_of_view))
            frame = frame or m.header.frame_id
        if rows:
            rangers[name] = np.array(sorted(rows))
            mounts[name] = mount(transforms, frame)
    beacons = sorted((m.header.stamp.to_sec(), m.beacon_id, m.range) for _, m, _ in bag.read_messages(topics=[BEACONS]))
    receiver = hal.get('beacons', {}).get('frame_id', 'beacon_receiver_link')
    mounts['beacon receiver'] = mount(transforms, receiver) or (0.0, 0.0, 0.0)
    return Signals(est, encoders, commands, rangers, mounts, np.array(beacons) if beacons else np.zeros((0, 3)))


def _applied_pwm(bag, hal):
    """{side: (t, u)} of the PWM the boards report applying (-1..1), for the drive wheels whose
    command topic lies under a board that publishes hcl_drivers/MotorBoardState."""
    boards = [t for t, info in bag.get_type_and_topic_info().topics.items()
              if info.msg_type == 'hcl_drivers/MotorBoardState']
    out = {}
    for side in ('left', 'right'):
        wheel = hal.get('drive', {}).get('wheels', {}).get(side, {})
        topic, motor = wheel.get('topic', ''), wheel.get('motor', side)
        board = next((b for b in boards if topic.startswith(b.rsplit('/', 1)[0] + '/')), None)
        if board is None:
            continue
        rows = []
        for _, m, _ in bag.read_messages(topics=[board]):
            if motor in m.motor_names and len(m.pwm_applied) == len(m.motor_names):
                rows.append((m.header.stamp.to_sec(), m.pwm_applied[list(m.motor_names).index(motor)] / 1000.0))
        if len(rows) > 10:
            a = np.array(sorted(rows))
            out[side] = (a[:, 0], np.clip(a[:, 1], -1.0, 1.0))
    return out


def pose_at(estimate, t):
    """(x, y, yaw) interpolated at times t; yaw unwrapped then wrapped."""
    x = np.interp(t, estimate[:, 0], estimate[:, 1])
    y = np.interp(t, estimate[:, 0], estimate[:, 2])
    a = np.interp(t, estimate[:, 0], np.unwrap(estimate[:, 3]))
    return x, y, a
