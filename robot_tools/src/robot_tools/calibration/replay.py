"""The check that closes `make calibrate` (scripts/calibrate.py): the match's recorded PWM commands
replayed through the simulator's own motor model (robot_sim's motor_replay, the code the simulated
world steps) with the config's values and with the fitted ones, and the encoder counts it gives
against the recording, second by second.

    error = sum over one-second windows |replayed counts - recorded counts| / sum |recorded counts|

Windows where the replay and the recording part by more than 4 spreads of the rest (the robot
pushing against something: the recording's wheel stood, the free model's did not) are left out
and counted.
"""
import os
import subprocess
import tempfile
import xmlrpc.client

import numpy as np

from robot_tools.calibration.stats import robust_mask

WINDOW = 1.0  # [s]


def motor_replay_binary():
    """robot_sim's motor_replay, from the sourced workspace."""
    try:
        found = subprocess.run(['catkin_find', '--first-only', 'robot_sim', 'motor_replay'], stdout=subprocess.PIPE,
                               stderr=subprocess.DEVNULL, universal_newlines=True).stdout.strip()
    except OSError:
        found = ''
    if found and os.access(found, os.X_OK):
        return found
    from robot_tools.paths import ROOT as root
    for devel in ('devel', 'devel_isolated', 'install'):
        path = os.path.join(root, devel, 'lib', 'robot_sim', 'motor_replay')
        if os.access(path, os.X_OK):
            return path
    return None


def replay_turns(binary, config, motor, t_cmd, u, t_query):
    """The wheel's turns at t_query under the commands (t_cmd, u), from the simulator's motor model."""
    events = [(t, 0, 'c %.6f %.6f' % (t, v)) for t, v in zip(t_cmd, u)] + \
             [(t, 1, 'q %.6f' % t) for t in t_query]
    events.sort()
    with tempfile.NamedTemporaryFile('w', suffix='.xml', delete=False) as f:
        f.write(xmlrpc.client.dumps(({'table': config.get('table', {}), 'sim': {'world': config['sim']['world']}},)))
        params = f.name
    try:
        done = subprocess.run([binary, params, motor], input='\n'.join(e[2] for e in events) + '\n',
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True, check=True)
    except subprocess.CalledProcessError as e:
        raise RuntimeError('motor_replay: %s' % e.stderr.strip())
    finally:
        os.unlink(params)
    return np.array([float(x) for x in done.stdout.split()])


def window_counts(t, counts, start, end):
    edges = np.arange(start, end, WINDOW)
    return np.diff(np.interp(edges, t, counts))


def counts_error(recorded, replayed):
    """(error, windows kept, windows left out) of the per-window counts."""
    recorded, replayed = np.asarray(recorded), np.asarray(replayed)
    if len(recorded) == 0:
        return float('nan'), 0, 0
    # the replay's direction and scale to counts are the encoder's (sign, mounting): one sign
    sign = 1.0 if float(recorded @ replayed) >= 0 else -1.0
    diff = sign * replayed - recorded
    keep = robust_mask(diff) | (np.abs(diff) <= 0.01 * np.abs(recorded))
    moving = np.sum(np.abs(recorded[keep]))
    if moving <= 0:
        return float('nan'), int(keep.sum()), int((~keep).sum())
    return float(np.sum(np.abs(diff[keep])) / moving), int(keep.sum()), int((~keep).sum())


def replay_error(binary, config, motor, ticks_per_rev, commands, encoder):
    """counts_error of one drive motor: its commands (t, u) replayed against its encoder (t, counts)."""
    t_cmd, u = commands
    t_enc, counts = encoder
    start, end = max(t_cmd[0], t_enc[0]), t_enc[-1]
    edges = np.arange(start, end, WINDOW)
    turns = replay_turns(binary, config, motor, t_cmd, u, edges)
    return counts_error(window_counts(t_enc, counts, start, end), np.diff(turns) * ticks_per_rev)
