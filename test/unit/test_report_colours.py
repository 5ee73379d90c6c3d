"""The start zones are drawn in their team's colour (robot_description/scripts/table_markers, which
rviz and the match report both draw from): Logion plays red from the top-left zone and that zone is
red, the 2009 robot's too, and a green robot's zone is green, whatever the zones' order."""
import importlib.machinery
import importlib.util
import os
import unittest

import yaml

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))


def load_table_markers():
    path = os.path.join(ROOT, 'robot_description', 'scripts', 'table_markers')
    loader = importlib.machinery.SourceFileLoader('table_markers', path)
    spec = importlib.util.spec_from_loader('table_markers', loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


def start_zone_colours(table):
    """{zone name: (r, g, b)} as drawn, matched by position."""
    tm = load_table_markers()
    markers = tm.table_markers(table, '/table', 'map')
    out = {}
    zones = [m for m in markers.markers if m.ns == 'start_zones']
    for zone, m in zip(table['start_zones'], zones):
        x0, y0, x1, y1 = zone['rect']
        assert abs(m.pose.position.x - (x0 + x1) / 2) < 1e-9 and abs(m.pose.position.y - (y0 + y1) / 2) < 1e-9
        out[zone['name']] = (m.color.r, m.color.g, m.color.b)
    return out


def dominant(rgb):
    return ('red', 'green', 'blue')[max(range(3), key=lambda i: rgb[i])]


class ReportColoursTest(unittest.TestCase):
    def table_of(self, robot):
        with open(os.path.join(ROOT, 'config', robot + '.yaml')) as f:
            return yaml.safe_load(f)['table']

    def test_each_robots_start_zones_are_drawn_in_their_teams_colour(self):
        for robot in ('logion', 'eurobot2009'):
            colours = start_zone_colours(self.table_of(robot))
            for name, rgb in colours.items():
                self.assertEqual(dominant(rgb), name, '%s: zone %s drawn %s' % (robot, name, rgb))

    def test_a_green_robot_listed_first_is_green(self):
        table = self.table_of('eurobot2009')
        table['start_zones'] = list(reversed(table['start_zones']))  # green first
        colours = start_zone_colours(table)
        self.assertEqual(dominant(colours['green']), 'green')
        self.assertEqual(dominant(colours['red']), 'red')


if __name__ == '__main__':
    unittest.main()
