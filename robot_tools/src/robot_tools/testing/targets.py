"""What the build offers as tests and what each one reported: catkin's run_tests_<pkg>_<kind>_<name>
targets, a rostest target's .test file and time limits, and its JUnit result files."""
import glob
import os
import re
import subprocess
import xml.etree.ElementTree as ET

from robot_tools.paths import ROOT

BUILD = os.path.join(ROOT, 'build')


def targets():
    """Every run_tests_<pkg>_<kind>_<name> target the build knows."""
    out = subprocess.run(['make', '-C', BUILD, 'help'], capture_output=True, text=True, check=True).stdout
    names = set(re.findall(r'\b(run_tests_[A-Za-z0-9_]+?_(?:gtest|nosetests|fuzz|rostest|vm)_\S+)', out))
    return sorted(names)


def package_dirs():
    dirs = {}
    for xml in glob.glob(os.path.join(ROOT, 'src', '*', 'package.xml')):
        name = ET.parse(xml).getroot().findtext('name')
        dirs[name] = os.path.realpath(os.path.dirname(xml))
    return dirs


def rostest_file(target, packages):
    """The .test file of a rostest target: its path in the package, '/' spelled '_' in the name."""
    for pkg, d in packages.items():
        prefix = 'run_tests_%s_rostest_' % pkg
        if target.startswith(prefix):
            flat = target[len(prefix):]
            for path in glob.glob(os.path.join(d, '**', '*.test'), recursive=True):
                if os.path.relpath(path, d).replace('/', '_') == flat:
                    return path
    return None


def time_limit(test_file):
    """The sum of the file's <test time-limit=...> (rostest's default is 60 s)."""
    root = ET.parse(test_file).getroot()
    return sum(float(t.get('time-limit', 60)) for t in root.iter('test'))


def result_file(target):
    """The JUnit file catkin's run_tests.py writes for a target (the first argument in its rule)."""
    for rule in glob.glob(os.path.join(BUILD, '*', 'CMakeFiles', target + '.dir', 'build.make')):
        m = re.search(r'run_tests\.py (\S+\.xml)', open(rule).read())
        if m:
            return m.group(1)
    return None


def result_files(target, test_file):
    """The JUnit files a target writes: catkin's, and for a rostest one per <test test-name=...>
    (rostest's own file says only whether the launch came up)."""
    path = result_file(target)
    if not path:
        return []
    files = [path]
    if test_file:
        files += [os.path.join(os.path.dirname(path), 'rosunit-%s.xml' % t.get('test-name'))
                  for t in ET.parse(test_file).getroot().iter('test')]
    return files


def result_failed(target, test_file):
    """True when one of the target's JUnit files is missing, unreadable or reports a failure or error."""
    files = result_files(target, test_file)
    for path in files:
        if not os.path.exists(path):
            return True
        try:
            root = ET.parse(path).getroot()
        except ET.ParseError:
            return True
        suites = [root] if root.tag == 'testsuite' else list(root.iter('testsuite'))
        if any(int(s.get('errors', 0) or 0) + int(s.get('failures', 0) or 0) for s in suites):
            return True
    return not files
