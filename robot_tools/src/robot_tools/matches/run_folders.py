"""Where a run writes: a folder of its own per run, never over an earlier one's, and a `latest`
link beside them to the last complete one.

    report/<robot>/<UTC time>_seed<k>/          one `make run`
    report/<robot>/matches_<UTC time>/          one `make matches` (a folder per match inside)
    report/<robot>/chaos_<UTC time>/            one `make chaos`
    report/<robot>/latest, matches_latest, chaos_latest   the last complete ones

A run that did not complete (it never started, its launch failed, it was interrupted) keeps what
it wrote, says why in INCOMPLETE, and leaves `latest` where it was.
"""
import os
import time

INCOMPLETE = 'INCOMPLETE'


def stamp():
    return time.strftime('%Y%m%dT%H%M%SZ', time.gmtime())


def new_folder(base, name):
    """A new folder `base/name` (made unique with a counter if a run already took the name)."""
    path = os.path.join(base, name)
    k = 1
    while os.path.exists(path):
        k += 1
        path = os.path.join(base, '%s_%d' % (name, k))
    os.makedirs(path)
    return path


def mark_incomplete(folder, why):
    with open(os.path.join(folder, INCOMPLETE), 'w') as f:
        f.write(why.rstrip() + '\n')


def mark_complete(folder, link_name='latest'):
    """Point `<folder's parent>/<link_name>` at `folder` (relative, replaced atomically)."""
    parent = os.path.dirname(os.path.abspath(folder))
    link = os.path.join(parent, link_name)
    tmp = '%s.tmp%d' % (link, os.getpid())
    if os.path.lexists(tmp):
        os.remove(tmp)
    os.symlink(os.path.basename(os.path.abspath(folder)), tmp)
    os.replace(tmp, link)
    return link
