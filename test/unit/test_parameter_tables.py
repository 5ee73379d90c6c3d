"""The parameter tables (make docs: hcl_drivers, hal_nodes, robot_sim, smart_brain, robot_description
and robot_core's PARAMETERS.md) are what
the readers declare: regenerated from the code, they equal the committed files; and they hold
what a reader asks for, with the default and the range it checks."""
import os
import subprocess
import sys
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))
TOOL = os.path.join(ROOT, 'scripts', 'parameter_tables.py')


def rows(package, section):
    """{parameter: [type, default, allowed, meaning]} of one section of a package's table."""
    out, inside = {}, False
    with open(os.path.join(ROOT, package, 'PARAMETERS.md')) as f:
        for line in f:
            if line.startswith('## '):
                inside = line.strip() == '## ' + section
            elif inside and line.startswith('| `'):
                cells = [c.strip() for c in line.strip().strip('|').split(' | ')]
                out[cells[0].strip('`')] = cells[1:]
    return out


class ParameterTablesTest(unittest.TestCase):
    def test_the_committed_tables_are_what_the_readers_declare(self):
        done = subprocess.run([sys.executable, TOOL, '--check'], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              universal_newlines=True)
        self.assertEqual(done.returncode, 0, done.stdout)

    def test_a_boards_defaults_and_ranges_come_from_its_reader(self):
        # HBmotor's reader (hcl_drivers/src/boards/i2c/hbmotor.cpp): command_timeout 0.3 and > 0,
        # firmware_watchdog 0.25 within 0 .. 2.55
        hbmotor = rows('hcl_drivers', 'HBMotor')
        self.assertEqual(hbmotor['command_timeout'][:3], ['number', '0.3', '> 0'])
        self.assertEqual(hbmotor['firmware_watchdog'][:3], ['number', '0.25', '0 .. 2.55'])
        every = rows('hcl_drivers', 'Every board')
        self.assertIn('rate', every)

    def test_every_parameter_says_what_it_means(self):
        # the meaning is the reader's own Params::describe beside the read: a new parameter
        # without one shows here, not as a silent blank in the docs
        blank = []
        for package in ('hcl_drivers', 'hal_nodes', 'robot_sim', 'smart_brain', 'robot_description', 'robot_core'):
            with open(os.path.join(ROOT, package, 'PARAMETERS.md')) as f:
                blank += ['%s: %s' % (package, l.split('|')[1].strip()) for l in f
                          if l.startswith('| `') and l.rstrip().endswith('|  |')]
        self.assertEqual(blank, [])

    def test_devices_and_the_world_have_tables(self):
        self.assertIn('initial_pose', rows('hal_nodes', 'Localization'))
        world = rows('robot_sim', 'sim/world')
        self.assertEqual(world['dt'][:3], ['number', '0.001', '0.0001 .. 0.02'])
        self.assertIn('robot/motors/<name>/max_speed', world)


    def test_the_brain_the_simulator_node_and_the_python_nodes_have_tables(self):
        brain = rows('smart_brain', 'brain')
        self.assertEqual(brain['rate'][:3], ['number', '10.0', '> 0'])
        self.assertEqual(brain['match/start'][:3], ['string', 'cord', 'one of: cord, immediate'])
        self.assertIn('approach', rows('smart_brain', 'brain/match2009'))
        self.assertIn('distance', rows('smart_brain', 'brain/triggers/opponent_ahead'))
        self.assertIn('realtime_priority', rows('robot_sim', 'sim (the simulator node)'))
        self.assertEqual(rows('robot_description', 'process_watch (~)')['nodes'][:2], ['list', 'required'])

    def test_the_emulators_the_hosts_and_the_shared_blocks_have_tables(self):
        # each emulator type's reader (robot_sim/src/firmware: Firmware::configure)
        epos = rows('robot_sim', 'sim/firmware/<name>: Epos')
        self.assertEqual(epos['nominal_rpm'][:3], ['number', '8000', '> 0'])
        self.assertEqual(rows('robot_sim', 'sim/firmware/<name>: SRF02')['address'][:3], ['integer', 'required', '112 .. 127'])
        self.assertIn('type', rows('robot_sim', 'Every emulator (`sim/firmware/<name>`)'))
        # the component hosts' own values (robot_core/host_settings.h)
        host = rows('hcl_drivers', '`hcl:` (hcl_node, the host of the boards)')
        self.assertEqual(host['realtime_priority'][:3], ['integer', '0', '0 .. 99'])
        self.assertIn('only', rows('hal_nodes', '`hal:` (hal_node, the host of the devices)'))
        # the blocks several packages read
        self.assertIn('length', rows('robot_core', 'table'))


if __name__ == '__main__':
    unittest.main()
