"""Params: the Python nodes' parameter reader, the twin of the C++ one (robot_core/params.h).

A reader asks for each value by name with its default and type (and, where it matters, what is
allowed and what the value means); the reader converts it, refuses a bad one with one line naming
the parameter, and remembers what was asked. From that memory come the brain's parameter table
(`make docs`: declarations()) and its typo check (unasked(): a key no reader knows).

    params = Params.from_server('~')          # one request to the master
    rate = params.value('rate', 10.0, float, rule='> 0', meaning='[Hz] decision loop rate')
    block = params.block('match')              # '~match', sharing what is asked
    raw = block('start_topic', '/hal/hmi/input')  # as it is, typed by its default
    names = params.block_names('zones')        # a dictionary of named blocks: the table says zones/<name>/..

The same reader runs on a YAML tree with no master (Params(tree, '/brain')), which is how the
config check and the table generator see a config before any node starts.
"""
import collections

Declaration = collections.namedtuple('Declaration', 'type required default rule meaning')
REQUIRED = object()  # the default of a value the config must give

_TYPE_NAMES = {float: 'number', int: 'integer', bool: 'boolean', str: 'string', list: 'list', dict: 'dictionary'}


class ParameterError(ValueError):
    """A parameter the config got wrong: the message names it (`parameter /brain/rate = 0: ...`)."""


def type_name(kind, value=None):
    """The table's type of a value read with converter `kind`, else of its default/value."""
    if kind in _TYPE_NAMES:
        return _TYPE_NAMES[kind]
    if isinstance(value, bool):
        return 'boolean'
    if isinstance(value, int):
        return 'integer'
    for k in (float, str, list, dict):
        if isinstance(value, k):
            return _TYPE_NAMES[k]
    return 'any'


def _written(value):
    """A default as the config would write it."""
    if value is None:
        return ''
    if isinstance(value, bool):
        return 'true' if value else 'false'
    if isinstance(value, str):
        return "''" if value == '' else value
    return str(list(value) if isinstance(value, tuple) else value)


class _Record(object):
    """What every Params over one tree was asked (shared by its blocks)."""

    def __init__(self):
        self.asked = set()      # qualified names (a dictionary read whole counts as asked throughout)
        self.blocks = set()     # dictionaries read key by key (block())
        self.block_maps = set()  # dictionaries of named blocks (block_names()): the table says <name>
        self.unused = set()     # whole subtrees left alone on purpose
        self.describing = False  # a reader run for its declarations: a missing required value is None
        self.declared = {}      # qualified name -> Declaration


class Params(object):
    def __init__(self, tree=None, ns='', record=None):
        self._tree = tree if isinstance(tree, dict) else {}
        self.ns = ns.rstrip('/')
        self._record = record if record is not None else _Record()

    @classmethod
    def from_server(cls, ns='~'):
        """Everything under `ns` on the parameter server, named as ROS resolves it."""
        import rospy
        return cls(rospy.get_param(ns, {}), rospy.resolve_name(ns))

    def qualified(self, key):
        return '%s/%s' % (self.ns, key)

    def has(self, key):
        return key in self._tree

    def keys(self):
        return list(self._tree)

    def block(self, key):
        """The dictionary `key` (empty when absent: every value at its default)."""
        self._record.blocks.add(self.qualified(key))
        value = self._tree.get(key)
        if value is not None and not isinstance(value, dict):
            raise ParameterError('parameter %s = %r: must be a dictionary' % (self.qualified(key), value))
        return Params(value or {}, self.qualified(key), self._record)

    def block_names(self, key):
        """The names of the dictionaries under the dictionary `key` (links: {camera_link: {..}, ..}),
        in the config's order; none when absent. What is read under them is declared
        `key/<name>/...`, as the C++ Params::blockNames."""
        self._record.block_maps.add(self.qualified(key))
        self._record.blocks.add(self.qualified(key))
        self._declare(key, 'dictionary of named blocks', {}, '')
        self._record.asked.discard(self.qualified(key))  # read entry by entry: a key no reader knows shows
        value = self._tree.get(key)
        if value is None:
            return []
        if not isinstance(value, dict):
            raise ParameterError('parameter %s = %r: must be a dictionary of named blocks'
                                 % (self.qualified(key), value))
        for name, entry in value.items():
            if not isinstance(entry, dict):
                raise ParameterError('parameter %s/%s = %r: must be a dictionary' % (self.qualified(key), name, entry))
        return list(value)

    def __call__(self, key, default=None):
        """The value as the config gives it (no conversion), typed in the table by its default."""
        value = self._tree.get(key, default)
        self._declare(key, type_name(None, default if default is not None else value), default, '')
        return value

    def value(self, key, default=REQUIRED, kind=None, allowed=None, rule='', meaning='', check=None,
              default_named=None):
        """The value converted by `kind` (float, int, bool, str, list, dict); one of `allowed`
        when given; `check(value)` -> a reason it is wrong (or '') for any other rule, written
        `rule` in the table. `default_named`: the table's default when `default` is taken from
        elsewhere ("the strategy's `timed`")."""
        if allowed is not None and not rule:
            rule = 'one of: ' + ', '.join(map(_written, allowed))
        self._declare(key, type_name(kind, None if default is REQUIRED else default), default, rule)
        if default_named:
            name = self.qualified(key)
            self._record.declared[name] = self._record.declared[name]._replace(default=default_named)
        if meaning:
            self.describe(key, meaning)
        if key not in self._tree:
            if default is REQUIRED:
                if self._record.describing:
                    return None
                raise ParameterError('missing required parameter %s' % self.qualified(key))
            return default
        value = self._tree[key]
        converted = self._convert(key, value, kind)
        if allowed is not None and converted not in allowed:
            raise ParameterError('parameter %s = %r: allowed values: %s'
                                 % (self.qualified(key), value, ', '.join(map(str, allowed))))
        reason = check(converted) if check is not None else ''
        if reason:
            raise ParameterError('parameter %s = %r: %s' % (self.qualified(key), value, reason))
        return converted

    def positive(self, key, default, meaning=''):
        """A number > 0."""
        value = self.value(key, default, float, rule='> 0', meaning=meaning,
                           check=lambda v: '' if v > 0 else 'must be a number > 0')
        return value

    def describe(self, key, meaning):
        """What `key` means, in a line: the meaning column of the parameter table."""
        name = self.qualified(key)
        seen = self._record.declared.get(name) or Declaration('', False, '', '', '')
        self._record.declared[name] = seen._replace(meaning=meaning)

    def unused(self, key):
        """A subtree this reader leaves alone in this configuration: not an unknown key."""
        self._record.unused.add(self.qualified(key))

    def declarations(self):
        """{name relative to this block: Declaration} of everything read under it."""
        prefix = self.ns + '/'
        out = {}
        for name, d in sorted(self._record.declared.items()):
            if not name.startswith(prefix):
                continue
            general = self._general(name)[len(prefix):]
            seen = out.get(general)
            if seen is None:
                out[general] = d
            else:  # one more entry of a dictionary of named blocks: the first read's type, a meaning from any
                out[general] = (seen if seen.type else d)._replace(meaning=seen.meaning or d.meaning)
        return out

    def unasked(self):
        """'<qualified name> = <value>' of every value under this block no reader asked for."""
        out = []
        self._collect(self._tree, self.ns, out)
        return out

    # ---- inside
    def _declare(self, key, type_, default, rule):
        name = self.qualified(key)
        self._record.asked.add(name)
        seen = self._record.declared.get(name)
        self._record.declared[name] = Declaration(type_, default is REQUIRED,
                                                  '' if default is REQUIRED else _written(default),
                                                  rule, seen.meaning if seen else '')

    def _general(self, name):
        """`name` with the entry of each dictionary of named blocks it is under written <name>."""
        for block in sorted(self._record.block_maps):
            head = block + '/'
            rest = name[len(head):]
            if name.startswith(head) and '/' in rest:
                name = head + '<name>' + rest[rest.index('/'):]
        return name

    def _convert(self, key, value, kind):
        if kind is None:
            return value
        name = type_name(kind)
        bad = ParameterError('parameter %s = %r: must be %s %s' % (self.qualified(key), value,
                                                                  'an' if name[0] in 'aeiou' else 'a', name))
        if kind is bool:
            if not isinstance(value, bool):
                raise bad
            return value
        if kind in (float, int) and (isinstance(value, bool) or not isinstance(value, (int, float))):
            raise bad
        if kind is int and int(value) != value:
            raise bad
        if kind in (list, dict) and not isinstance(value, kind):
            raise bad
        if kind is str and isinstance(value, (dict, list)):
            raise bad
        return kind(value)

    def _collect(self, tree, path, out):
        for key in sorted(tree, key=str):
            name = '%s/%s' % (path, key)
            if name in self._record.unused or name in self._record.asked:
                continue
            if name in self._record.blocks and isinstance(tree[key], dict):
                self._collect(tree[key], name, out)
            elif name not in self._record.blocks:
                out.append('%s = %r' % (name, tree[key]))


def declaration_lines(params, component):
    """What a reader declared, a tab-separated line per parameter: component, name, type,
    required|optional, default, allowed, meaning (the rows `make docs` turns into a table).
    `component(name)` -> (table, name in it)."""
    lines = []
    for name, d in sorted(params.declarations().items()):
        table, key = component(name)
        lines.append('\t'.join((table, key, d.type, 'required' if d.required else 'optional', d.default, d.rule,
                                d.meaning)))
    return lines


def describe_node(node, read, argv):
    """A Python node's `--describe` (make docs): when argv holds it, prints what `read(params)`
    declares over an empty private namespace (every default) as `node` rows and returns True."""
    if '--describe' not in argv:
        return False
    params = Params({}, '~')
    params._record.describing = True
    read(params)
    print('\n'.join(declaration_lines(params, lambda name: (node, name))))
    return True
