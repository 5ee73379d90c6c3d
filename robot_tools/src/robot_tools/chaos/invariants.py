"""What a match with injected faults must still do (`make chaos`, scripts/run_chaos.py), judged
from its bag and the injector's log (robot_tools.chaos.injector: each fault's actual start and
end, simulated time). Every check returns violations as (time [s of match], text).

  no motor runs blind  a non-zero PWM on a motor board (the emulator's own state,
                       /sim/<board>/firmware) only while the HAL commanded a non-zero speed
                       (/hcl/<board>/motor/*/command) within the board's command timeout plus its
                       watchdog, only within the watchdog of the last command frame the board
                       received (its command_age), and never with the HCL dead for longer than
                       the watchdog; by header stamps, never by the recorder's receive times
  the fault is named   /diagnostics: its status (chaos_faults.expected_status) at ERROR or STALE
                       within NAMED_WITHIN of its start, back to OK within CLEARED_WITHIN of its end
  nothing is lost      every periodic topic of the bag keeps coming for the whole match: no gap
                       over max(GAP_MIN, GAP_PERIODS periods) except while its publisher, or the
                       recorder, was dead (until it was back and started: RESTART_ALLOWANCE, in
                       wall seconds: a restarted publisher is found again by the recorder in wall
                       time, so at a real-time factor of 3 it is 3 x as long in the bag's time)
  the match ends       the effectors are off EFFECTORS_GRACE after the match end, or hal_node is
                       dead then (nothing is commanded)
  the robot recovers   after a fault's end, /mcl/pose within RECOVERED_M of the truth again (and
                       for SETTLED) within RECOVER_WITHIN; after a HAL or HCL restart, counted
                       from the first pose the restarted HAL publishes
"""
import bisect
import collections
import statistics

from robot_tools.chaos.faults import expected_status
from robot_tools.report.match_bag import stamp_of
from robot_tools.report.metrics import errors_against_truth

NAMED_WITHIN = 1.0        # [s]
CLEARED_WITHIN = 2.0      # [s]
GAP_MIN, GAP_PERIODS = 1.0, 10.0
RESTART_ALLOWANCE = 5.0   # [s, wall] after a respawned node answers, until its topics flow again
EFFECTORS_GRACE = 1.0     # [s]
RECOVERED_M, RECOVER_WITHIN = 0.05, 5.0
SETTLED = 1.0             # [s] the error stays below RECOVERED_M this long to count as back
OK, ERROR = 0, 2

RECORDER_BUFFER = 1.0     # [s] a recorder killed -9 loses the chunk it had not written yet
RECORDER_RESTART = 10.0   # [s, wall] a respawned recorder subscribes again to every recorded topic, which
                          # takes seconds after the recorder answers on a loaded machine

#: Which process publishes a topic (first matching prefix and suffix); None: several, or the simulator.
#: The HAL commands the boards on /hcl/<board>/...; the emulated camera serves frames to the HCL,
#: and the emulated SRF02s and CMPS03 publish their truth when the HCL's driver asks them for a
#: reading over I2C (/sim/<chip>/range, /bearing): all of these pause with their requester.
OWNERS = (('/hcl/', '/command', '/hal'), ('/hcl/', '/pulse_us', '/hal'), ('/hcl/', '/target', '/hal'),
          ('/hcl/', '/lcd', '/hal'), ('/hcl/', '/outputs', '/hal'), ('/hcl/', '/lamp_pwm', '/hal'),
          ('/hcl/', '', '/hcl'), ('/sim/camera/', '', '/hcl'),
          ('/sim/', '/range', '/hcl'), ('/sim/', '/bearing', '/hcl'), ('/hal/', '', '/hal'),
          ('/mcl/', '', '/hal'), ('/odom', '', '/hal'), ('/tf', '', '/hal'), ('/effectors/', '', '/hal'),
          ('/brain/', '', '/brain'))
#: Topics that carry events, not a stream: action goals, results and feedback (however often a
#: strategy retries), velocity commands (only while driving), log lines, state machine
#: introspection, the simulator's fault log.
EVENT_TOPICS = ('/feedback', '/goal', '/result', '/cancel', '/cmd_vel', '/rosout', '/container_status',
                '/container_structure', '/injected')
#: A board that is silent (or off its bus, or sending garbage) sends nothing: what is computed
#: from it pauses with it. Not a loss: nothing was there to record.
BUS_KINDS = ('board_silent', 'can_bus_off', 'serial_garbage', 'serial_truncate')
#: A dead process also starves what is computed from it.
DOWNSTREAM = {'/hcl': ('/hcl', '/hal'), '/hal': ('/hal', '/brain'), '/brain': ('/brain',), '/record': ()}


def dead_windows(faults):
    """{node: [(start, end)]}: when each killed or stalled process was not running."""
    out = collections.defaultdict(list)
    for f in faults:
        if f['kind'] in ('kill', 'stall'):
            out[f['target']].append((f['start'], f['end']))
    return out


def wall_to_sim(fault, wall_seconds):
    """`wall_seconds` in the bag's (simulated) time: times the real-time factor the injector
    measured over the fault (never less than real time)."""
    return wall_seconds * max(1.0, float(fault.get('factor', 1.0)))


def restart_windows(faults, node, before, wall_after):
    """[(start - before, end + wall_after in simulated s)] of the process faults of `node`."""
    return [(f['start'] - before, f['end'] + wall_to_sim(f, wall_after))
            for f in faults if f['kind'] in ('kill', 'stall') and f['target'] == node]


def _inside(t, windows, before=0.0, after=0.0):
    return any(a - before <= t <= b + after for a, b in windows)


def blind_samples(samples, commands, window, watchdog, margin, hcl_dead=(), unrecorded=()):
    """The motor board samples that drove blind: [(stamp, why)]. Every time is a header stamp
    (the publisher's clock at the moment), never the recorder's receive time: under load the
    recorder stamps late and in batches, and a command received after the PWM it caused would
    look like no command at all.
      samples   [(stamp, bag time, [pwm], command_age or None)] the board's own state
      commands  sorted stamps of the HAL's non-zero motor commands
      window    how long after a non-zero command a PWM may stay non-zero (command timeout of the
                HCL + the board's watchdog + a sample period + margin)
      watchdog  the board's watchdog [s]: it may drive no longer than this after its last command
                frame on the bus (command_age: what the board says of that)
      hcl_dead  (start, end) the HCL was killed or stalled; unrecorded: (start, end) of bag time
                the recorder was down (the bag cannot tell then)."""
    blind = []
    for stamp, bag_time, pwm, command_age in samples:
        if not any(pwm) or any(a <= bag_time <= b for a, b in unrecorded):
            continue
        i = bisect.bisect_right(commands, stamp)
        if i == 0 or stamp - commands[i - 1] > window:
            blind.append((stamp, 'no non-zero command for %.2f s' % (stamp - commands[i - 1] if i else float('inf'))))
        elif command_age is not None and command_age > watchdog + margin:
            blind.append((stamp, 'the board drove %.2f s after its last command frame (watchdog %.2f s)'
                          % (command_age, watchdog)))
        elif any(a <= stamp - (watchdog + margin) and stamp <= b for a, b in hcl_dead):
            blind.append((stamp, 'the HCL dead for longer than the %.2f s watchdog' % watchdog))
    return blind


def no_motor_runs_blind(m, config, faults, t0):
    out = []
    dead = dead_windows(faults)
    hcl_dead = dead.get('/hcl', [])
    unrecorded = restart_windows(faults, '/record', RECORDER_BUFFER, RESTART_ALLOWANCE)
    for topic in m.find('/sim/', '/firmware'):
        board = topic.split('/')[2]
        block = config.get('hcl', {}).get(board, {})
        samples = []
        for _, msg, t in m.read(topic):
            values = dict(zip(msg.names, msg.values))
            pwm = [v for n, v in values.items() if n.startswith('pwm')]
            if pwm:
                samples.append((stamp_of(msg, t), t.to_sec(), pwm, values.get('command_age')))
        if len(samples) < 2:
            continue
        samples.sort()
        period = statistics.median(b[0] - a[0] for a, b in zip(samples, samples[1:]))
        watchdog = float(block.get('watchdog_ms', 0)) / 1000.0
        margin = period + 0.05
        window = float(block.get('command_timeout', 0.25)) + watchdog + margin
        commands = sorted(stamp_of(msg, t) for c in m.find('/hcl/%s/motor/' % board, '/command')
                          for _, msg, t in m.read(c) if msg.value != 0)
        blind = blind_samples(samples, commands, window, watchdog, margin, hcl_dead, unrecorded)
        if blind:
            out.append((blind[0][0] - t0, 'motor blind: %s: non-zero PWM %d time(s), first: %s (window %.2f s)'
                        % (board, len(blind), blind[0][1], window)))
    return out


def statuses(m):
    """{status name: [(bag time, level, message)]} of /diagnostics."""
    out = collections.defaultdict(list)
    for _, msg, t in m.read('/diagnostics'):
        for s in msg.status:
            out[s.name].append((t.to_sec(), s.level, s.message))
    return out


def faults_named(m, faults, t0, series=None):
    out = []
    series = series if series is not None else statuses(m)
    recorder_dead = restart_windows(faults, '/record', 0.0, RECORDER_RESTART)  # down, or not subscribed yet
    for f in faults:
        name = expected_status(f)
        if name is None or f['outcome'].startswith(('REFUSED', 'FAILED')):
            continue
        what = '%s %s' % (f['kind'], f.get('target', ''))
        if _inside(f['start'], recorder_dead, after=NAMED_WITHIN) or _inside(f['end'], recorder_dead, after=CLEARED_WITHIN):
            continue  # the recorder was down: the bag cannot tell
        points = series.get(name, [])
        named_within, cleared_within = NAMED_WITHIN, CLEARED_WITHIN
        if f['kind'] in ('kill', 'stall'):
            named_within, cleared_within = wall_to_sim(f, NAMED_WITHIN), wall_to_sim(f, CLEARED_WITHIN)
        named = [t for t, level, _ in points if f['start'] <= t <= f['start'] + named_within and level >= ERROR]
        if not named:
            seen = [(t - f['start'], level, msg) for t, level, msg in points
                    if f['start'] <= t <= f['start'] + named_within]
            out.append((f['start'] - t0, '%s not named on "%s" at ERROR/STALE within %.1f s (there: %s)'
                        % (what, name, named_within, sorted({(lv, msg[:60]) for _, lv, msg in seen}) or 'nothing')))
            continue
        cleared = [t for t, level, _ in points if t >= max(f['end'], named[0]) and level == OK]
        if not cleared or cleared[0] > f['end'] + cleared_within:
            late = ('%.2f s after its end' % (cleared[0] - f['end'])) if cleared else 'never'
            out.append((f['end'] - t0, '%s: "%s" not back to OK within %.1f s of the fault\'s end (%s)'
                        % (what, name, cleared_within, late)))
    return out


def owner(topic):
    for prefix, suffix, node in OWNERS:
        if topic.startswith(prefix) and topic.endswith(suffix):
            return node
    return None


def quiet_board_topics(f, config):
    """Topic fragments of what a bus fault silences: its board (the whole CAN bus for bus-off),
    and what the HAL computes from the boards."""
    if f['kind'] not in BUS_KINDS:
        return ()
    derived = ('/hal/', '/mcl/', '/odom', '/tf')  # the HAL computes from the boards
    if f['kind'] == 'can_bus_off':
        return derived + tuple('/%s/' % n for n, b in config.get('hcl', {}).items()
                               if isinstance(b, dict) and 'node_id' in b)
    if f['kind'].startswith('serial_') or f.get('target') == 'beacons':
        return derived + ('/beacons/',)
    return derived + ('/%s/' % f['target'],)


def merged(windows, join_within):
    """The union of the windows, joining two that are less than join_within apart: a gap that one
    excuse after another covers (the HAL restarted, then the recorder) is excused."""
    out = []
    for a, b in sorted(windows):
        if out and a - join_within <= out[-1][1]:
            out[-1] = (out[-1][0], max(out[-1][1], b))
        else:
            out.append((a, b))
    return out


def nothing_lost(m, faults, start, end, t0, config):
    out = []
    dead = dead_windows(faults)
    quiet = [(quiet_board_topics(f, config), f['start'], f['end']) for f in faults]
    excused_for = collections.defaultdict(list)  # node -> windows its topics may pause, allowance included
    for node in dead:
        for affected in DOWNSTREAM.get(node, (node,)):
            excused_for[affected] += restart_windows(faults, node, 0.0, RESTART_ALLOWANCE)
    everything = restart_windows(faults, '/record', RECORDER_BUFFER, RECORDER_RESTART)
    for topic in sorted(m.topics):
        if topic.endswith(EVENT_TOPICS):
            continue
        times = [t.to_sec() for _, _, t in m.bag.read_messages(topics=[topic]) if start <= t.to_sec() <= end]
        if len(times) < 20:
            continue  # event topics (goals, results, score events): no period to keep
        period = statistics.median(b - a for a, b in zip(times, times[1:]))
        if period > 0.5:
            continue
        allowed = max(GAP_MIN, GAP_PERIODS * period)
        excused = excused_for.get(owner(topic), []) + everything + \
            [(a, b + RESTART_ALLOWANCE) for fragments, a, b in quiet if any(p in topic for p in fragments)]
        excused = merged(excused, allowed)
        for a, b in zip([start] + times, times + [end]):
            if b - a <= allowed:
                continue
            if any(wa - allowed <= a and b <= we for wa, we in excused):
                continue
            out.append((a - t0, 'lost: %s silent for %.2f s (allowed %.2f s)' % (topic, b - a, allowed)))
            break
    return out


def match_ends(m, faults, end, t0, effectors_off_delay):
    if end is None:
        return [(0.0, 'the match never ended')]
    if _inside(end, dead_windows(faults).get('/hal', []), after=EFFECTORS_GRACE):
        return []  # hal_node dead at the end: no effector is commanded; it comes back deactivated
    if effectors_off_delay(m, end) is None:
        return [(end - t0, 'the effectors were still on %.0f s after the match end' % EFFECTORS_GRACE)]
    return []


def first_settled(errors):
    """The first time the error is below RECOVERED_M and stays below for SETTLED seconds (an
    estimate that merely has not yet seen a kidnap is not a recovery), or None."""
    for k, (t, e, _) in enumerate(errors):
        if e >= RECOVERED_M:
            continue
        later = [e2 for t2, e2, _ in errors[k:] if t2 <= t + SETTLED]
        if errors[-1][0] >= t + SETTLED and max(later) < RECOVERED_M:
            return t
    return None


def first_pose_after_recorder_gap(times, since, recorder_down):
    """When the recorder was down during [since, since + RECOVER_WITHIN] and the bag holds no
    pose for more than a second of it: the first pose recorded after that gap, else None."""
    for a, b in recorder_down:
        if a > since + RECOVER_WITHIN or b < since:
            continue
        k = bisect.bisect_left(times, max(since, a))
        previous = times[k - 1] if k > 0 else max(since, a)
        for t in times[k:]:
            if t > b + RECOVER_WITHIN:
                break
            if t - previous > 1.0:
                return t
            previous = t
    return None


def recoveries(m, faults, end):
    """[(fault, since, back or None, worst)] for each injected fault that ended RECOVER_WITHIN
    before the match end: when the localization had to be back from (its end; after a HAL or HCL
    restart, the restarted HAL's first pose; when the recorder was down meanwhile, its first pose
    recorded again), when it was back within RECOVERED_M for SETTLED, and the worst error meanwhile."""
    out = []
    errors = errors_against_truth(m.poses('/mcl/pose'), m.poses('/sim/ground_truth'))
    times = [t for t, _, _ in errors]
    recorder_down = restart_windows(faults, '/record', 0.0, RECORDER_RESTART)
    for f in faults:
        if f['outcome'].startswith(('REFUSED', 'FAILED')) or end is None or f['end'] + RECOVER_WITHIN > end:
            continue
        i = bisect.bisect_left(times, f['end'])
        since = f['end']
        if f['kind'] == 'kill' and f.get('target') in ('/hal', '/hcl') and i < len(times):
            since = times[i]  # from the restarted HAL's first pose: it loads its devices first
        back_on = first_pose_after_recorder_gap(times, since, recorder_down)
        if back_on is not None:
            since = back_on  # the bag cannot tell before: judged from the restarted recorder's first pose
        back = first_settled(errors[i:])
        worst = max((e for t, e, _ in errors[i:] if t <= since + RECOVER_WITHIN), default=float('nan'))
        out.append((f, since, back, worst))
    return out


def robot_recovers(m, faults, end, t0, found=None):
    """`found`: recoveries() already computed for this match (one reading of the bag)."""
    out = []
    for f, since, back, worst in (found if found is not None else recoveries(m, faults, end)):
        if back is None or back > since + RECOVER_WITHIN:
            out.append((f['end'] - t0, 'not recovered: localization not within %.0f cm of the truth %.0f s after '
                        '%s %s ended (%s; worst %.3f m)' % (100 * RECOVERED_M, RECOVER_WITHIN, f['kind'],
                                                            f.get('target', ''), 'back %.1f s after' % (back - f['end'])
                                                            if back else 'never', worst)))
    return out


#: The classes of violations (the first words of their text), for summaries.
CLASSES = (('motor blind', 'motor blind'), ('false alarm', 'false alarm'), ('not recovered', 'not recovered'),
           ('lost:', 'lost'), ('the effectors', 'match end'), ('the match never', 'match end'),
           ('node ', 'process died'), ('run_match', 'run failed'), ('no bag', 'run failed'),
           ('our robot left', 'off the table'))


def violation_class(text):
    """The class of a violation's text: 'motor blind', 'not named', ... ('other' for none)."""
    if ' not named on ' in text or 'not back to OK' in text:
        return 'not named'
    if ' was not injected' in text:
        return 'not injected'
    for prefix, name in CLASSES:
        if text.startswith(prefix):
            return name
    return 'other'
