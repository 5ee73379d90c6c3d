"""`make docs`: each package's parameter tables, written from the parameter readers themselves.

    scripts/parameter_tables.py [--check]

Every shipped robot's config (config/ROBOT.yaml, with and without its sim overlay) goes through
the readers the nodes run at start, with no master (robot_core's check_components for the boards
and the devices, robot_sim's check_sim_config for the simulator, its world and its emulators), each asked with --describe what it
declared of every parameter it read: its type, whether it is required, its default and what is
allowed, what it means: Params::describe beside the read). One table per board type
(hcl_drivers/PARAMETERS.md), device type (hal_nodes/PARAMETERS.md), the simulator and its world
and each emulator type (robot_sim/PARAMETERS.md) and the brain, its strategies and triggers (smart_brain/PARAMETERS.md,
smart_brain's check_brain_config); the parameters every board or device type reads come first, once.
The blocks several packages read (robot: through robot_description's robot_urdf, table: through the
world's reader, computer/network) are robot_core's (robot_core/PARAMETERS.md).
The Python nodes whose parameters a launch file sets (NODES: robot_description's) are asked once
each, `<node> --describe`, one table per node (robot_description/PARAMETERS.md).
With --check nothing is written: exit 1 and the files that differ from what the code declares
(the test that keeps the committed tables in sync)."""
import argparse
import collections
import glob
import os
import subprocess
import sys
import tempfile

import yaml
from robot_core.config_tree import merged

from robot_tools.paths import ROOT

# (package whose table it is, the tool, its arguments after the config, a title per table)
SOURCES = (
    ('hcl_drivers', 'robot_core', 'check_components', ['hcl', 'hcl_drivers', 'board', '--describe'], 'board'),
    ('hal_nodes', 'robot_core', 'check_components', ['hal', 'hal_nodes', 'device', '--describe'], 'device'),
    ('robot_sim', 'robot_sim', 'check_sim_config', ['--describe'], 'world'),
    ('smart_brain', 'smart_brain', 'check_brain_config', ['--describe'], 'brain'),
    ('robot_core', 'robot_description', 'robot_urdf', ['--describe'], 'robot_core'),  # the robot: block
)
# Python nodes whose parameters a launch file sets, not a robot's config: (package, its nodes),
# each asked once with --describe (robot_core.params.describe_node).
NODES = (
    ('robot_description', ('diagnostics_markers', 'network_guard', 'process_watch', 'table_markers')),
)
# Python readers of a shared block, asked once with --describe: (package whose table it is, the command).
MODULES = (
    ('robot_core', [sys.executable, '-m', 'robot_core.network_settings', '--describe']),  # computer/network
)
Declaration = collections.namedtuple('Declaration', 'type required default rule meaning')
FIRMWARE = 'firmware:'  # check_sim_config's component name of an emulator type: firmware:TYPE
# The blocks of a robot's config that several packages read (the description, the table, the
# robot's network): wherever a reader declares them, their table is robot_core's.
SHARED = ('robot', 'table', 'computer/network')
SHARED_PACKAGE = 'robot_core'
HOST = '(host)'  # check_components' component name of the host's own values (hcl_node's, hal_node's)
HOSTS = {'board': '`hcl:` (hcl_node, the host of the boards)', 'device': '`hal:` (hal_node, the host of the devices)'}


def robots():
    """The shipped robots: config/ROBOT.yaml beside a launch/ROBOT.launch."""
    names = [os.path.basename(p)[:-len('.launch')] for p in glob.glob(os.path.join(ROOT, 'launch', '*.launch'))]
    return sorted(n for n in names if os.path.exists(os.path.join(ROOT, 'config', n + '.yaml')))


def load(path):
    with open(path) as f:
        return yaml.safe_load(f) or {}


def configs():
    """(name, merged tree) of every robot's config, alone and with its sim overlay."""
    for robot in robots():
        base = load(os.path.join(ROOT, 'config', robot + '.yaml'))
        yield robot, base
        sim = os.path.join(ROOT, 'config', robot + '.sim.yaml')
        if os.path.exists(sim):
            yield robot + ' (sim)', merged(base, load(sim))


def tool(package, name):
    found = subprocess.run(['catkin_find', '--first-only', package, name], stdout=subprocess.PIPE,
                           stderr=subprocess.DEVNULL, universal_newlines=True).stdout.strip()
    if not found:
        sys.exit('parameter_tables: %s/%s not found: build the workspace (make build) and source devel/setup.bash'
                 % (package, name))
    return found


def described(text):
    """(component, parameter, Declaration) of each line a reader's --describe printed."""
    for line in text.splitlines():
        component, pname, ptype, required, default, rule, meaning = line.split('\t')
        yield component, pname, Declaration(ptype, required == 'required', default, rule, meaning)


def declarations():
    """{table kind: {component type: {name: Declaration}}} over every config; a default that
    differs between configs (one computed from another value) is shown as each."""
    out = {kind: collections.defaultdict(dict) for _, _, _, _, kind in SOURCES}
    for package, nodes in NODES:
        out[package] = collections.defaultdict(dict)
        for name in nodes:
            done = subprocess.run([tool(package, name), '--describe'], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                  universal_newlines=True)
            if done.returncode != 0:
                sys.exit('parameter_tables: %s --describe failed:\n%s' % (name, done.stderr))
            for component, pname, d in described(done.stdout):
                out[package][component][pname] = d
    for package, command in MODULES:
        done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True)
        if done.returncode != 0:
            sys.exit('parameter_tables: %s failed:\n%s' % (' '.join(command[1:]), done.stderr))
        for component, pname, d in described(done.stdout):
            out[package][component][pname] = d
    for label, tree in configs():
        with tempfile.NamedTemporaryFile('w', suffix='.yaml', prefix='parameter_tables_') as f:
            yaml.safe_dump(tree, f)
            f.flush()
            for _, package, name, args, kind in SOURCES:
                done = subprocess.run([tool(package, name), f.name] + args, stdout=subprocess.PIPE,
                                      stderr=subprocess.PIPE, universal_newlines=True)
                if done.returncode != 0:
                    sys.exit('parameter_tables: %s refused %s:\n%s' % (name, label, done.stderr))
                for component, pname, d in described(done.stdout):
                    target = out[SHARED_PACKAGE if component in SHARED else kind]
                    seen = target[component].get(pname)
                    if seen and not d.type:  # described, not read, in this config: what another read says
                        continue
                    default = d.default
                    if seen and default not in seen.default.split(' or '):
                        default = seen.default + ' or ' + default
                    target[component][pname] = d._replace(default=default,
                                                             meaning=d.meaning or (seen.meaning if seen else ''))
    return out


def cell(text):
    return text.replace('|', '\\|') if text else ''


def table(rows):
    """The markdown rows of one table."""
    lines = ['| parameter | type | default | allowed | meaning |', '|---|---|---|---|---|']
    for name, d in sorted(rows.items()):
        if not d.type:  # described where no shipped config has it read: nothing the reader declared
            continue
        default = 'required' if d.required else cell(d.default)
        lines.append('| `%s` | %s | %s | %s | %s |' % (name, cell(d.type), default, cell(d.rule), cell(d.meaning)))
    return lines


def title(kind, component):
    """The heading of one component's table."""
    if component == HOST:
        return HOSTS[kind]
    if kind == 'robot_description':
        return component + ' (~)'
    if kind == 'world':
        return {'world': 'sim/world', 'simulator': 'sim (the simulator node)'}.get(
            component, 'sim/firmware/<name>: ' + component[len(FIRMWARE):])
    if kind == 'brain':
        return 'brain' if component == 'brain' else 'brain/' + component
    return component


def document(package, kind, components):
    """The text of PACKAGE/PARAMETERS.md."""
    what = {'board': 'board type (the `type:` of an `hcl:` block)', 'device': 'device type (the `type:` of a `hal:` block)',
            'world': 'the simulator node (`sim:` of a robot\'s sim overlay), its world (`sim/world`) and '
                     'emulator type (the `type:` of a `sim/firmware` block)',
            'robot_description': 'node (its private parameters, set by the robot\'s launch file)',
            SHARED_PACKAGE: 'block of a robot\'s config that several packages read (`robot:` the description, '
                            '`table:` the game table, `computer/network` the robot\'s network)',
            'brain': 'the brain node\'s own values (`brain:` of a robot\'s config), each strategy\'s block '
                     '(`brain/<strategy>`) and each trigger\'s (`brain/triggers/<kind>`)'}[kind]
    lines = ['# %s parameters' % package, '',
             'Written by `make docs` (`scripts/parameter_tables.py`) from the parameter readers themselves: ' +
             ('each' if kind in dict(NODES) else 'every'),
             'node\'s reader, run with `--describe`, declares what it reads (type, required or default, what is'
             if kind in dict(NODES) else
             'shipped robot\'s config goes through the reader each node runs at start, which declares what it',
             'allowed, what it means). Do not edit by hand:' if kind in dict(NODES) else
             'read (type, required or default, what is allowed, what it means). Do not edit by hand:',
             '`test_parameter_tables` fails when this file and the code disagree. Per %s.' % what,
             '`<name>`: any name of your own (an entry of a dictionary of named blocks); `x[]/key`: a key of each',
             'dictionary in the list `x`.', '']
    # the component types of one plugin kind, whose common parameters come first, once
    family = {'board': 'board', 'device': 'device', 'world': 'emulator'}.get(kind)
    members = sorted(t for t in components if (kind != 'world' or t.startswith(FIRMWARE)) and t != HOST)
    common = {}
    if family and len(members) > 1:
        shared = set.intersection(*(set(components[t]) for t in members))
        common = {n: components[members[0]][n] for n in shared
                  if all(components[t][n].type == components[members[0]][n].type for t in members)}
    for t in sorted(components, key=lambda t: (t in members, t)):
        if common and t == members[0]:
            lines += ['## Every %s' % family + (' (`sim/firmware/<name>`)' if kind == 'world' else ''), ''] + \
                table(common) + ['']
        own = {n: d for n, d in components[t].items() if n not in common or t not in members}
        lines += ['## %s' % title(kind, t), ''] + (table(own) if own else
                                           ['Only the parameters every %s reads.' % (family or kind)]) + ['']
    return '\n'.join(lines).rstrip() + '\n'


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--check', action='store_true', help='write nothing; exit 1 when a committed table differs')
    args = ap.parse_args(argv)
    found = declarations()
    stale = []
    tables = [(package, kind) for package, _, _, _, kind in SOURCES] + [(p, p) for p, _ in NODES]
    for package, kind in tables:
        path = os.path.join(ROOT, package, 'PARAMETERS.md')
        text = document(package, kind, found[kind])
        old = open(path).read() if os.path.exists(path) else None
        if old == text:
            continue
        if args.check:
            stale.append(os.path.relpath(path, ROOT))
        else:
            with open(path, 'w') as f:
                f.write(text)
            print('parameter_tables: wrote %s (%d tables)' % (os.path.relpath(path, ROOT), len(found[kind])))
    if stale:
        print('parameter_tables: %s differ(s) from what the readers declare: run make docs' % ', '.join(stale))
        return 1
    if args.check:
        print('parameter_tables: the committed tables match the readers')
    return 0


if __name__ == '__main__':
    sys.exit(main())
