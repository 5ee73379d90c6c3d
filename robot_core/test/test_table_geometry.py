"""The Python table geometry against the vectors test_table_geometry.cpp checks too."""
import math
import os
import random
import unittest

import yaml

from robot_core.table_geometry import TableGeometry

VECTORS = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'table_geometry_vectors.yaml')


class TableGeometryTest(unittest.TestCase):
    def test_shared_vectors(self):
        with open(VECTORS) as f:
            doc = yaml.safe_load(f)
        table = TableGeometry(doc['table']['length'], doc['table']['width'], doc['table']['blocks'])
        self.assertGreaterEqual(len(doc['cases']), 10)
        for case in doc['cases']:
            x, y, angle = case['apex']
            got = table.cone_range(x, y, angle, case['beam_width'], case['circles'])
            self.assertAlmostEqual(got, case['range'], places=9, msg=case['name'])

    def test_cone_range_is_the_minimum_over_a_dense_ray_fan(self):
        table = TableGeometry(3.0, 2.1, [(1.3, 0.0, 1.7, 0.3), (0.0, 1.8, 0.4, 2.1)])
        rng = random.Random(7)
        for _ in range(60):
            x, y, a, width = rng.uniform(0.05, 2.95), rng.uniform(0.05, 2.05), rng.uniform(-math.pi, math.pi), \
                rng.uniform(0.0, 1.2)
            circles = [(rng.uniform(0.05, 2.95), rng.uniform(0.05, 2.05), rng.uniform(0.05, 0.2))]
            fan = min(table.ray_range(x, y, a + width * (k / 2000.0 - 0.5), circles) for k in range(2001))
            cone = table.cone_range(x, y, a, width, circles)
            self.assertLessEqual(cone, fan + 1e-9)
            self.assertGreaterEqual(cone, fan - 4e-3)

    def test_rays_and_edges(self):
        table = TableGeometry(3.0, 2.1, [(1.3, 0.0, 1.7, 0.3)])
        self.assertAlmostEqual(table.ray_range(1.0, 1.0, 0.0), 2.0, places=12)
        self.assertAlmostEqual(table.ray_range(1.0, 1.0, 0.0, [(1.5, 1.0, 0.1)]), 0.4, places=12)
        self.assertAlmostEqual(table.ray_range(1.0, 1.0, math.pi, [(1.5, 1.0, 0.1)]), 1.0, places=12)
        self.assertEqual(table.ray_range(float('nan'), 1.0, 0.0), 0.0)
        self.assertAlmostEqual(table.distance_to_edge(1.5, 0.5), 0.2, places=12)
        self.assertFalse(table.open(1.5, 0.2))
        self.assertRaises(ValueError, TableGeometry, 0.0, 2.1)
