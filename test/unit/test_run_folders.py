"""Reports are kept (robot_tools.matches.run_folders): each run writes to a folder of its own, `latest` points
to the last complete one, and a run that failed keeps what it wrote, says why in INCOMPLETE and
leaves `latest` on the last good report."""
import os
import shutil
import tempfile
import unittest

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
from robot_tools.matches import run_folders


class RunFoldersTest(unittest.TestCase):
    def setUp(self):
        self.base = tempfile.mkdtemp(prefix='run_folders_')

    def tearDown(self):
        shutil.rmtree(self.base, ignore_errors=True)

    def test_a_failed_run_leaves_latest_on_the_last_good_report(self):
        good = run_folders.new_folder(self.base, '20261127T120000Z_seed1')
        with open(os.path.join(good, 'eurobot2009_match.png'), 'w') as f:
            f.write('good')
        link = run_folders.mark_complete(good)
        self.assertEqual(os.path.realpath(link), os.path.realpath(good))
        failed = run_folders.new_folder(self.base, '20261127T120500Z_seed1')
        with open(os.path.join(failed, 'eurobot2009_launch.log'), 'w') as f:
            f.write('[FATAL] parameter ~strategy = mach: unknown strategy')
        run_folders.mark_incomplete(failed, 'the robot never became ready')
        self.assertEqual(os.path.realpath(os.path.join(self.base, 'latest')), os.path.realpath(good))
        with open(os.path.join(self.base, 'latest', 'eurobot2009_match.png')) as f:
            self.assertEqual(f.read(), 'good')
        self.assertTrue(os.path.exists(os.path.join(failed, 'eurobot2009_launch.log')))  # its log is kept
        with open(os.path.join(failed, run_folders.INCOMPLETE)) as f:
            self.assertIn('never became ready', f.read())

    def test_two_runs_in_the_same_second_get_two_folders(self):
        a = run_folders.new_folder(self.base, 'x')
        b = run_folders.new_folder(self.base, 'x')
        self.assertNotEqual(a, b)
        self.assertTrue(os.path.isdir(a) and os.path.isdir(b))
        run_folders.mark_complete(a, 'matches_latest')
        run_folders.mark_complete(b, 'matches_latest')  # replaced, not an error
        self.assertEqual(os.path.realpath(os.path.join(self.base, 'matches_latest')), os.path.realpath(b))
        self.assertRegex(run_folders.stamp(), r'^\d{8}T\d{6}Z$')


if __name__ == '__main__':
    unittest.main()
