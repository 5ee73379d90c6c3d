"""The tools (the commands in scripts/ and the modules of robot_tools, where their code lives) never
use a module before the function that imports it does: Python then makes the name local to the
whole function and the earlier use fails at run time (UnboundLocalError), on a path a test may not
take. Read from the source, nothing imported or run."""
import ast
import glob
import os
import unittest

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))


def used_before_import(tree):
    """[(function, name, line used, line imported)] of every function in the module."""
    out = []
    for func in ast.walk(tree):
        if not isinstance(func, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        imported = {}
        for node in ast.walk(func):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                for alias in node.names:
                    name = (alias.asname or alias.name).split('.')[0]
                    imported[name] = min(imported.get(name, node.lineno), node.lineno)
        for node in ast.walk(func):
            if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load) and node.id in imported \
                    and node.lineno < imported[node.id]:
                out.append((func.name, node.id, node.lineno, imported[node.id]))
    return out


def sources(*folder):
    """Every Python file under ROOT/folder, subfolders included."""
    return sorted(glob.glob(os.path.join(ROOT, *folder + ('**', '*.py')), recursive=True))


class ToolImportsTest(unittest.TestCase):
    def test_no_module_is_used_before_its_import(self):
        scripts, package = sources('scripts'), sources('robot_tools', 'src', 'robot_tools')
        self.assertGreater(len(scripts), 20)
        self.assertGreater(len(package), 20)
        found = []
        for path in scripts + package:
            with open(path) as f:
                tree = ast.parse(f.read(), path)
            found += ['%s: %s() uses %s at line %d, imports it at line %d' % ((os.path.relpath(path, ROOT),) + hit)
                      for hit in used_before_import(tree)]
        self.assertEqual(found, [])

    def test_the_check_catches_the_case(self):
        tree = ast.parse('def main(out):\n    if out is None:\n        out = run_folders.new()\n    import run_folders\n')
        self.assertEqual(used_before_import(tree), [('main', 'run_folders', 3, 4)])


if __name__ == '__main__':
    unittest.main()
