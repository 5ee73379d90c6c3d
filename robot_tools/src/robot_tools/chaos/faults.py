"""The chaos runner's faults (`make chaos`, scripts/run_chaos.py): every fault class a robot
can suffer, drawn into a schedule per match, and what each one must show on /diagnostics.

A fault is {at: [s of match time], kind, target, duration: [s], magnitude, class}; `at` and
the simulated durations are in simulated time, `stall` lasts `duration` wall seconds (a process
frozen is a wall-clock event). Kinds (robot_tools.chaos.injector injects them):
  on the buses   board_silent, can_bus_off, can_reset, can_malformed (a CAN board; the last two
                 are instants: the board reboots / sends one malformed frame), serial_garbage,
                 serial_truncate (the beacon receiver), beacon_silent (one beacon on the table),
                 board_silent on an I2C chip (a NACK storm)
  in the world   wheel_slip, kidnap (30 cm), opponent_blocks
  in processes   kill of /hcl, /hal, /brain, /record (roslaunch respawns them), stall of /hal
"""
import random

SPACING = 9.0          # [s] one slot per fault; it starts at a random time in its slot's first JITTER
JITTER = 3.0           # seconds, so two faults start at least SPACING - JITTER apart
FIRST, LAST = 8.0, 10.0  # [s] no fault in the first FIRST and last LAST seconds of the match
# [s, wall] SIGSTOP of hal_node: a stall by process_watch's rule whatever its loop's phase. It
# names two probes of 0.2 s in a row unanswered, with its other nodes' probes and its 0.1 s
# period in between: a stop only just longer than that can still be answered at the second probe
# on a busy machine (then only a WARN "slow to answer"), and a rule on the watcher's phase is no rule.
STALL = 1.0


def catalogue(config):
    """Every fault class this robot has: {class name: function(rng) -> fault}."""
    hcl = {name: block for name, block in config.get('hcl', {}).items() if isinstance(block, dict)}
    can = sorted(n for n, b in hcl.items() if 'node_id' in b)
    i2c = sorted(n for n, b in hcl.items() if 'address' in b)  # an I2C chip has its address
    serial = sorted(n for n, b in hcl.items() if b.get('type') == 'BeaconReceiver')
    motors = sorted(m for m in config['sim']['world']['robot'].get('motors', {}) if m in ('left', 'right'))
    beacons = len(config.get('table', {}).get('beacons', [])) or 3
    out = {}

    def fault(cls, kind, target='', duration=0.0, magnitude=0.0):
        return dict(kind=kind, target=target, duration=duration, magnitude=magnitude, **{'class': cls})

    if can:
        out['board_silent'] = lambda r: fault('board_silent', 'board_silent', r.choice(can), 2.0)
        out['can_bus_off'] = lambda r: fault('can_bus_off', 'can_bus_off', r.choice(can), 2.0)
        out['can_reset'] = lambda r: fault('can_reset', 'can_reset', r.choice(can))
        out['can_malformed'] = lambda r: fault('can_malformed', 'can_malformed', r.choice(can))
    if i2c:
        out['i2c_nack_storm'] = lambda r: fault('i2c_nack_storm', 'board_silent', r.choice(i2c), 2.0)
    if serial:
        out['serial_garbage'] = lambda r: fault('serial_garbage', 'serial_garbage', serial[0], 2.0)
        out['serial_truncate'] = lambda r: fault('serial_truncate', 'serial_truncate', serial[0], 2.0)
        out['beacon_silent'] = lambda r: fault('beacon_silent', 'beacon_silent', str(r.randrange(beacons)), 3.0)
    if motors:
        out['wheel_slip'] = lambda r: fault('wheel_slip', 'wheel_slip', r.choice(motors), 1.5)
    out['kidnap'] = lambda r: fault('kidnap', 'kidnap', magnitude=0.3)
    if 'opponent' in config['sim']['world']:
        out['opponent_blocks'] = lambda r: fault('opponent_blocks', 'opponent_blocks', duration=3.0)
    for node in ('hcl', 'hal', 'brain', 'record'):
        out['kill_' + node] = (lambda n: lambda r: fault('kill_' + n, 'kill', '/' + n))(node)
    out['stall_hal'] = lambda r: fault('stall_hal', 'stall', '/hal', STALL)
    return out


def draw_schedules(config, n, seed, duration):
    """n schedules, one per match: the fault classes shuffled (seeded) and dealt out in turn, as
    many per match as fit SPACING apart, so N matches together cover every class."""
    rng = random.Random(seed)
    classes = catalogue(config)
    slots = max(1, int((duration - FIRST - LAST) // SPACING))
    deck, schedules = [], []
    for _ in range(n):
        faults = []
        for k in range(slots):
            if not deck:
                deck = sorted(classes)
                rng.shuffle(deck)
            f = classes[deck.pop()](rng)
            f['at'] = round(FIRST + k * SPACING + rng.uniform(0.0, JITTER), 2)
            faults.append(f)
        schedules.append(faults)
    return schedules


def expected_status(fault):
    """The /diagnostics status name that must name this fault, or None (world faults: the
    robot shows them by its position, judged by the recovery)."""
    kind, target = fault['kind'], fault.get('target', '')
    if kind in ('kill', 'stall'):
        return 'process ' + target
    if kind in ('board_silent', 'can_bus_off', 'can_reset', 'can_malformed', 'serial_garbage', 'serial_truncate'):
        return 'hcl/%s: board' % target
    if kind == 'beacon_silent':
        return 'hcl/beacons: board'
    return None
