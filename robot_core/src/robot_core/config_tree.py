"""A robot's configuration as the launch loads it: one YAML file over another, as `rosparam load`
merges them (a dictionary updates key by key, any other value replaces). One answer for the
config checker, the URDF writer and the match runner."""


def merged(base, over):
    """`over` merged into a copy of `base`."""
    out = dict(base)
    for key, value in over.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = merged(out[key], value)
        else:
            out[key] = value
    return out
