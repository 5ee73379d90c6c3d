"""What `make calibrate` writes (scripts/calibrate.py): the two overlays, the report and its PNG.

  config/<robot>.calibrated.yaml      over config/<robot>.yaml: the odometry's ticks per metre, the
                                      robot's track width (which the HAL devices read; also any block
                                      that shares it by YAML alias) and wheel radius (the robot block:
                                      what the URDF, the devices and the checks read)
  config/<robot>.calibrated.sim.yaml  over config/<robot>.sim.yaml, in the simulator's own names:
                                      sim/world/robot/{wheel_radius, wheel_base, motors/<m>/{max_speed,
                                      time_constant, dead_band}, slip/{per_accel, noise_std},
                                      rangers/<r>/{noise_std, noise_rel, bias}}, sim/world/beacons/noise_std
Both load with a launch's overlay:= and with OVERLAY=.
"""
import yaml


def alias_paths(text, path):
    """Every key path of the YAML `text` whose value is the same node as the one at `path` (a
    value the config shares by alias, &track_width / *track_width), `path` included."""
    root = yaml.compose(text)
    target = root
    for key in path:
        target = next(v for k, v in target.value if k.value == key)
    found = []

    def walk(node, at):
        if node is target:
            found.append(tuple(at))
        if isinstance(node, yaml.MappingNode):
            for k, v in node.value:
                walk(v, at + [k.value])
        elif isinstance(node, yaml.SequenceNode):
            for i, v in enumerate(node.value):
                walk(v, at + [i])
    walk(root, [])
    return found


def nested(pairs):
    """{a: {b: value}} from [((a, b), value)]."""
    out = {}
    for path, value in pairs:
        d = out
        for k in path[:-1]:
            d = d.setdefault(k, {})
        d[path[-1]] = value
    return out


def write_overlay(path, header, pairs):
    with open(path, 'w') as f:
        f.write(header)
        yaml.safe_dump(nested(pairs), f, default_flow_style=False, sort_keys=True)


def value_line(name, fit, was, unit=''):
    """'name: value +- sigma unit (config: was)'."""
    sigma = '' if fit.sigma is None else ' +- %.3g' % fit.sigma
    before = '' if was is None else ' (config: %.6g)' % was
    return '  %-44s %.6g%s%s%s' % (name, fit.value, sigma, unit, before)


def plot(path, robot, panels):
    """The report's PNG: one axis per (title, [(x, y, label)], xlabel, ylabel)."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(len(panels), 1, figsize=(10, 3.2 * len(panels)))
    axes = axes if len(panels) > 1 else [axes]
    fig.suptitle('make calibrate: %s' % robot, weight='bold')
    for ax, (title, series, xlabel, ylabel) in zip(axes, panels):
        for x, y, label in series:
            ax.plot(x, y, '.', ms=2, label=label)
        ax.set_title(title, loc='left')
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.grid(alpha=0.3)
        if len(series) > 1:
            ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)
