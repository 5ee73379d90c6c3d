"""False alarms: a diagnostic at ERROR or STALE during the match that no injected fault explains
(`make matches`, where nothing is injected, and `make chaos`). A team watching the Match panel
must be able to take every ERROR for a real fault.

A fault explains, from its start until an allowance after its end,
  the status that names it          its board's (hcl/<board>: board; every CAN board for a bus-off),
                                    the killed or stalled process's (process /<node>);
  what is computed from it          a bus fault: the HAL's devices; a killed or stalled /hcl: every
                                    board and device; /hal: every device and the brain's process;
  what it does to the robot         the world's faults: the devices that see it (localization,
                                    odometry, the driver, the drive, the rangers and bumpers).
Statuses before the start signal are the start-up; after the match end, the stop.
"""
ERROR, STALE = 2, 3
NAMED_AFTER = 2.0      # [s] after a fault's end its own status is back (chaos_invariants' CLEARED_WITHIN)
RECOVERED_AFTER = 5.0  # [s] what is computed from it, and the robot, are back (RECOVER_WITHIN)
RESTART_AFTER = 10.0   # [s, wall] a killed process is back and its topics flow again (respawn, recorder)
# [s] a fault's window opens this much before its start: the simulator applies a fault in the step
# that reaches its start, before it publishes that step's /clock, so a node that reports it at
# once stamps it (and the recorder files it) at the previous /clock, a step earlier.
CLOCK_LEAD = 0.05

BUS_KINDS = ('board_silent', 'can_bus_off', 'can_reset', 'can_malformed', 'serial_garbage', 'serial_truncate')
#: The devices that see what a world fault does to the robot.
WORLD_EFFECTS = {
    'beacon_silent': ('hcl/beacons: board', 'hal/beacons: device', 'hal/localization: device'),
    'wheel_slip': ('hal/odometry: device', 'hal/localization: device', 'hal/driver: device', 'hal/drive: device'),
    'kidnap': ('hal/localization: device', 'hal/driver: device', 'hal/drive: device'),
    'opponent_blocks': ('hal/driver: device', 'hal/drive: device', 'hal/rangers: device', 'hal/bumpers: device'),
}


def _board(name):
    return name.startswith('hcl/') and name.endswith(': board')


def _device(name):
    return name.startswith('hal/') and name.endswith(': device')


def can_boards(config):
    """The config's CAN boards (a bus-off silences them all)."""
    return sorted(n for n, b in config.get('hcl', {}).items() if isinstance(b, dict) and 'node_id' in b)


def explains(fault, name, config):
    """(explained, allowance after the fault's end [s, match time]) of status `name` by `fault`."""
    kind, target = fault['kind'], fault.get('target', '')
    factor = max(1.0, float(fault.get('factor', 1.0)))  # wall seconds of a process fault in match time
    if kind in ('kill', 'stall'):
        node = target.strip('/')
        if name == 'process ' + target:
            return True, RESTART_AFTER * factor
        downstream = {'hcl': lambda n: _board(n) or _device(n), 'hal': lambda n: _device(n) or n == 'process /brain'}
        if node in downstream and downstream[node](name):
            return True, RESTART_AFTER * factor + RECOVERED_AFTER
        return False, 0.0
    if kind in BUS_KINDS:
        boards = can_boards(config) if kind == 'can_bus_off' else [target]
        if name in ['hcl/%s: board' % b for b in boards]:
            return True, NAMED_AFTER
        return _device(name), RECOVERED_AFTER
    if kind in WORLD_EFFECTS:
        return name in WORLD_EFFECTS[kind], RECOVERED_AFTER
    return False, 0.0


def false_alarms(series, start, end, faults, t0, config):
    """[(match time, text)]: each episode of a status at ERROR or STALE between `start` and `end`
    (bag times) that begins outside every window of a fault explaining it. `series`: {status
    name: [(bag time, level, message)]} (chaos_invariants.statuses); `faults`: the injector's
    log (start, end, kind, target, outcome); `t0`: bag time of match time 0."""
    injected = [f for f in faults if not str(f.get('outcome', '')).startswith(('REFUSED', 'FAILED'))]
    out = []
    for name in sorted(series):
        bad_before = False
        for t, level, message in series[name]:
            bad = level in (ERROR, STALE) and start <= t <= end
            if bad and not bad_before:
                excused = False
                for f in injected:
                    yes, after = explains(f, name, config)
                    excused = excused or (yes and f['start'] - CLOCK_LEAD <= t <= f['end'] + after)
                if not excused:
                    out.append((t - t0, 'false alarm: "%s" %s at %.1f s, no fault explains it: %s'
                                % (name, 'ERROR' if level == ERROR else 'STALE', t - t0, (message or '')[:120])))
            bad_before = bad
    return out


def count(violations):
    """How many of [(t, text)] are false alarms."""
    return sum(1 for _, text in violations if text.startswith('false alarm:'))

