"""Calibration run, for `make calibrate` (docs/calibrate.md): UMBmark's square, driven
counter-clockwise then clockwise, `rounds` times each way, with a stop at every corner and a turn
in place there, and again until the match ends. Straight legs and turns both ways, stops between them, and the beacons in view
the whole time: what the fit of the wheels, the track width and the motors needs, in about a
minute. On the table: `roslaunch ... sim:=false record:=true strategy:=calibration`.

Config (~calibration): square [x0, y0, side] (the first corner, the side [m]; keep it clear of
the borders by the robot's radius), rounds (default 1), exec_timeout per leg [s] (default 15).
"""
import math

from robot_core.params import REQUIRED

from smart_brain.machine_strategy import MachineStrategy
from smart_brain.steps import build_sequence
from smart_brain.strategy import StrategyError, register


def square_steps(x0, y0, side, rounds, exec_timeout):
    """goto steps round the square: counter-clockwise `rounds` times, then clockwise; each corner
    reached facing the next leg (the driver stops there and turns in place)."""
    ccw = [(x0 + side, y0, math.pi / 2), (x0 + side, y0 + side, math.pi), (x0, y0 + side, -math.pi / 2), (x0, y0, 0.0)]
    cw = [(x0, y0 + side, 0.0), (x0 + side, y0 + side, -math.pi / 2), (x0 + side, y0, math.pi), (x0, y0, math.pi / 2)]
    steps = [dict(action='goto', x=x0, y=y0, angle=0.0, exec_timeout=exec_timeout, label='00_START_CORNER')]
    for way, corners in (('CCW', ccw), ('CW', cw)):
        for r in range(rounds):
            for k, (x, y, a) in enumerate(corners):
                steps.append(dict(action='goto', x=x, y=y, angle=round(a, 6), exec_timeout=exec_timeout,
                                  on_abort='continue', label='%s%d_CORNER%d' % (way, r + 1, k + 1)))
    return steps


@register
class CalibrationStrategy(MachineStrategy):
    name = 'calibration'
    description = "drive UMBmark's square both ways, stopping at each corner: the run make calibrate fits"
    required_devices = ('driver',)

    parameters = {
        'square': '[m] the square: its first corner and its side',
        'rounds': 'times round the square each way',
        'exec_timeout': '[s] longest drive to one corner',
    }

    def read_config(self, brain, table):
        MachineStrategy.read_config(self, brain, table)
        square = self.params.value('square', REQUIRED, list, rule='[x0, y0, side], side > 0')
        if square is not None and not (len(square) == 3 and float(square[2]) > 0):  # None: read to be described
            raise StrategyError('parameter ~calibration/square = %r: give [x0, y0, side] in metres (side > 0)' % (square,))
        self.square = [float(v) for v in square or ()]
        self.rounds = self.params.value('rounds', 1, int, rule='>= 1', check=lambda v: '' if v >= 1 else 'at least 1')
        self.exec_timeout = self.params.positive('exec_timeout', 15.0)

    def build(self):
        x0, y0, side = self.square
        steps = square_steps(x0, y0, side, self.rounds, self.exec_timeout)
        return build_sequence(steps, '~calibration/square', default_attempts=1)
