"""The tools are one Python package, robot_tools (robot_tools/src/robot_tools, installed with the
workspace): every module imports from the sourced workspace alone, no module or command changes
sys.path, the modules' imports of each other form no cycle, and no module outgrows ~400 lines."""
import ast
import glob
import os
import subprocess
import sys
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))
PACKAGE = os.path.join(ROOT, 'robot_tools', 'src')
LONGEST = 450  # lines: "no module over ~400"


def modules():
    """{dotted name: path} of every module of robot_tools."""
    out = {}
    for path in glob.glob(os.path.join(PACKAGE, 'robot_tools', '**', '*.py'), recursive=True):
        name = os.path.relpath(path, PACKAGE)[:-len('.py')].replace(os.sep, '.')
        out[name[:-len('.__init__')] if name.endswith('.__init__') else name] = path
    return out


def imported(path, known):
    """The robot_tools modules a file imports, wherever the import statement stands."""
    found = set()
    with open(path) as f:
        tree = ast.parse(f.read(), path)
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names if a.name in known)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            if node.module in known:
                found.add(node.module)
            found.update('%s.%s' % (node.module, a.name) for a in node.names if '%s.%s' % (node.module, a.name) in known)
    return found


class ToolsPackageTest(unittest.TestCase):
    def test_every_module_imports_from_the_workspace(self):
        names = sorted(modules())
        self.assertGreaterEqual(len(names), 25)
        code = 'import importlib, sys\nfor n in %r:\n    importlib.import_module(n)\n' % names
        done = subprocess.run([sys.executable, '-c', code], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              universal_newlines=True, cwd='/')  # nothing of the checkout on the path
        self.assertEqual(done.returncode, 0, done.stdout)

    def test_nothing_changes_sys_path(self):
        files = list(modules().values()) + glob.glob(os.path.join(ROOT, 'scripts', '**', '*.py'), recursive=True)
        offenders = []
        for p in files:
            with open(p) as f:
                if 'sys.path' in f.read():
                    offenders.append(os.path.relpath(p, ROOT))
        self.assertEqual(offenders, [])

    def test_the_import_graph_has_no_cycle(self):
        known = modules()
        graph = {name: imported(path, known) - {name} for name, path in known.items()}
        state, cycles = {}, []

        def visit(node, trail):
            state[node] = 'open'
            for nxt in sorted(graph[node]):
                if state.get(nxt) == 'open':
                    cycles.append(trail[trail.index(nxt):] + [nxt] if nxt in trail else trail + [nxt])
                elif nxt not in state:
                    visit(nxt, trail + [nxt])
            state[node] = 'done'
        for name in sorted(graph):
            if name not in state:
                visit(name, [name])
        self.assertEqual(cycles, [], 'import cycles: %s' % [' -> '.join(c) for c in cycles])

    def test_no_module_outgrows_one_concern(self):
        long = []
        for p in modules().values():
            with open(p) as f:
                long.append((sum(1 for _ in f), os.path.relpath(p, ROOT)))
        self.assertEqual([f for f in long if f[0] > LONGEST], [])

    def test_the_commands_are_thin_entry_points(self):
        for name in ('run_match', 'run_matches', 'run_chaos', 'tune', 'match_report', 'calibrate', 'robot_install',
                     'scoreboard', 'soak', 'new_robot', 'replay', 'compass_offset', 'parameter_tables'):
            with open(os.path.join(ROOT, 'scripts', name + '.py')) as f:
                text = f.read()
            self.assertIn('from robot_tools.', text, name)
            self.assertLess(len(text.splitlines()), 10, '%s: a command is an entry point, its code lives in robot_tools' % name)


if __name__ == '__main__':
    unittest.main()
