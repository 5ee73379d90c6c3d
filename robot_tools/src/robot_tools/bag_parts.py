"""The match bag when its recorder was restarted mid-match: robot_description's record_bag
keeps each earlier recorder's bag as NAME.partN.bag (or NAME.partN.bag.active for a recorder
that was killed: unindexed until `rosbag reindex`). `join` reindexes them and merges every
part and the last recorder's bag into NAME.bag, in time order, then removes the parts."""
import glob
import os
import re
import subprocess


def parts(bag):
    """The part files of `bag` (NAME.partN.bag and NAME.partN.bag.active), in order."""
    stem = bag[:-4] if bag.endswith('.bag') else bag
    found = glob.glob(glob.escape(stem) + '.part*.bag') + glob.glob(glob.escape(stem) + '.part*.bag.active')
    return sorted(found, key=lambda p: int(re.search(r'\.part(\d+)\.bag', p).group(1)))


def join(bag):
    """Merge the parts into `bag`; returns what was done (None without parts)."""
    found = parts(bag)
    if not found:
        return None
    import rosbag
    inputs = []
    for p in found + [bag, bag + '.active']:
        if not os.path.exists(p):
            continue
        if p.endswith('.active'):  # killed: no index; reindex writes it in place
            subprocess.run(['rosbag', 'reindex', '--quiet', p], check=False, stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL)
            for backup in glob.glob(p[:-len('.active')] + '.orig.active') + glob.glob(p + '.orig.active'):
                os.remove(backup)
        inputs.append(p)
    merged = bag + '.joined'
    count = 0
    with rosbag.Bag(merged, 'w', compression=rosbag.Compression.LZ4) as out:  # as the recorder writes
        readers = [rosbag.Bag(p, allow_unindexed=False) for p in inputs]
        import heapq
        streams = [r.read_messages(raw=True, return_connection_header=True) for r in readers]
        for topic, msg, t, header in heapq.merge(*streams, key=lambda m: m[2]):
            out.write(topic, msg, t, raw=True, connection_header=header)
            count += 1
        for r in readers:
            r.close()
    for p in inputs:
        os.remove(p)
    os.rename(merged, bag)
    return 'joined %d part(s) into %s (%d messages)' % (len(inputs), bag, count)
