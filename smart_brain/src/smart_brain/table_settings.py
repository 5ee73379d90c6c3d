"""TableSettings: the values of the table description (/table, the `table:` block of
config/<robot>.yaml) the brain uses, read once by one reader (robot_core.params) and handed to
the strategies (read_config), their world view and the triggers.

The rest of /table (beacons, border height, ...) belongs to other nodes: no typo check here.
"""
from robot_core.params import ParameterError, Params

NAMESPACE = '/table'


class TableSettings(object):
    def __init__(self, params):
        """`params`: a Params over /table."""
        self.length = params.value('length', 3.0, float, meaning='[m] the table along x (map frame, REP-103)')
        self.width = params.value('width', 2.1, float, meaning='[m] the table along y')
        self.elements = params.value('elements', [], list,
                                     meaning='the game elements at the start: [{kind, at: [x, y], ..}]')
        self.score_zones = params.value('score_zones', [], list,
                                        meaning='where elements score: [{name, rect, kinds, points, team}]')
        self.start_zones = params.value('start_zones', [], list,
                                        meaning='where a robot starts, naming its colour: [{name, rect}]')

    @property
    def size(self):
        """(length, width) [m]."""
        return self.length, self.width

    @classmethod
    def from_server(cls):
        """/table as the parameter server holds it (one request)."""
        return cls(Params.from_server(NAMESPACE))

    @classmethod
    def of(cls, table):
        """`table` as TableSettings: itself, or read from a /table dictionary (a config file's
        `table:`; None or {}: every value at its default)."""
        if isinstance(table, cls):
            return table
        if table is not None and not isinstance(table, dict):
            raise ParameterError('parameter %s = %r: must be a dictionary' % (NAMESPACE, table))
        return cls(Params(table or {}, NAMESPACE))
