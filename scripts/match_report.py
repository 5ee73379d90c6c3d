#!/usr/bin/env python3
"""Match report: one PNG (and the same summary as text) from any recorded bag.

    scripts/match_report.py [BAG] [-o OUT.png]      (make report [BAG=...])

BAG defaults to the newest *.bag in ~/.ros (where record:=true puts them). The figure shows
  1. the estimated trajectory (/mcl/pose; /odom when there is no /mcl/pose) against the true one
     (/sim/ground_truth, simulation only) on the table;
  2. the localization error over time (estimate vs truth, position and heading);
  3. the brain's states over time (any /brain/... topic carrying a state: smach-style
     container status `active_states`, or a `state` / `data` string);
  4. a text summary: duration, score (a /sim/...score... topic), errors (/rosout ERROR/FATAL,
     /diagnostics ERROR/STALE), trigger firings (/brain/...trigger... topics or log lines).
A topic that is not in the bag is listed as absent; nothing here needs a running ROS master or
the project's message packages (rosbag rebuilds message classes from the bag itself).
"""
import argparse
import glob
import math
import os
import sys

import matplotlib
matplotlib.use('Agg')  # headless: no display needed
import matplotlib.pyplot as plt  # noqa: E402
import rosbag  # noqa: E402

DEFAULT_TABLE = (3.0, 2.1)
ERROR_LEVELS = (8, 16)  # rosgraph_msgs/Log ERROR, FATAL


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def pose_of(msg):
    """(x, y, yaw) of a PoseWithCovarianceStamped, Odometry or PoseStamped; None otherwise."""
    p = getattr(msg, 'pose', None)
    if p is None:
        return None
    p = getattr(p, 'pose', p)  # PoseWithCovariance -> Pose
    if not hasattr(p, 'position'):
        return None
    return p.position.x, p.position.y, yaw_of(p.orientation)


def stamp_of(msg, t):
    h = getattr(msg, 'header', None)
    if h is not None and h.stamp.to_sec() > 0:
        return h.stamp.to_sec()
    return t.to_sec()


class Match(object):
    """Everything the report needs, read in one pass over the bag."""

    def __init__(self, path):
        self.path = path
        self.bag = rosbag.Bag(path)
        info = self.bag.get_type_and_topic_info().topics
        self.topics = {t: (i.msg_type, i.message_count) for t, i in info.items()}
        self.start = self.bag.get_start_time() if self.topics else 0.0
        self.end = self.bag.get_end_time() if self.topics else 0.0

    def has(self, topic):
        return topic in self.topics

    def find(self, prefix, word=''):
        return sorted(t for t in self.topics if t.startswith(prefix) and word in t)

    def poses(self, topic):
        out = []
        if not self.has(topic):
            return out
        for _, msg, t in self.bag.read_messages(topics=[topic]):
            p = pose_of(msg)
            if p is not None:
                out.append((stamp_of(msg, t),) + p)
        out.sort()
        return out

    def table(self):
        """(length, width) from the recorded /table_markers, else the default table."""
        if self.has('/table_markers'):
            for _, msg, _ in self.bag.read_messages(topics=['/table_markers']):
                for m in getattr(msg, 'markers', []):
                    if m.ns == 'table':
                        return m.scale.x, m.scale.y
        return DEFAULT_TABLE

    def brain_states(self):
        """(topic, [(t, state)]): the brain's active state over time. From the state machine's
        introspection (<brain>/smach/container_status: the chain of active states from the root
        container down, e.g. MATCH/TAKE_COLUMN/GOTO), else from a /brain/ topic with a `state`."""
        for topic in self.find('/brain/', 'container_status'):
            latest, states = {}, []
            for _, msg, t in self.bag.read_messages(topics=[topic]):
                latest[msg.path] = list(msg.active_states)
                root = min(latest, key=lambda p: (p.count('/'), len(p)))
                parts, path = [], root
                while latest.get(path):
                    parts.append(latest[path][0])
                    path = path + '/' + latest[path][0]
                label = '/'.join([root.strip('/')] + parts)
                if not states or states[-1][1] != label:
                    states.append((stamp_of(msg, t), label))
            if states:
                return topic, states
        for topic in self.find('/brain/'):
            states = []
            for _, msg, t in self.bag.read_messages(topics=[topic]):
                name = None
                if isinstance(getattr(msg, 'state', None), str):
                    name = msg.state
                elif isinstance(getattr(msg, 'current_state', None), str):
                    name = msg.current_state
                elif isinstance(getattr(msg, 'data', None), str) and 'state' in topic:
                    name = msg.data
                if name is None:
                    break
                if not states or states[-1][1] != name:
                    states.append((stamp_of(msg, t), name))
            if states:
                return topic, states
        return None, []

    def match_status(self):
        """The brain's last /brain/match_status (state, strategy, elapsed), or None."""
        last = None
        for topic in self.find('/brain/', 'match_status'):
            for _, msg, _ in self.bag.read_messages(topics=[topic]):
                last = msg
        return last

    def score(self):
        for topic in self.find('/sim/', 'score') + self.find('/brain/', 'score'):
            last = None
            for _, msg, _ in self.bag.read_messages(topics=[topic]):
                for field in ('score', 'data', 'points', 'total'):
                    v = getattr(msg, field, None)
                    if isinstance(v, (int, float)) and not isinstance(v, bool):
                        last = v
                        break
            if last is not None:
                return topic, last
        return None, None

    def errors(self):
        """(rosout error lines, diagnostics names that went ERROR or STALE)."""
        lines, diag = [], set()
        if self.has('/rosout'):
            for _, msg, _ in self.bag.read_messages(topics=['/rosout']):
                if getattr(msg, 'level', 0) in ERROR_LEVELS:
                    lines.append('%s: %s' % (msg.name, msg.msg.splitlines()[0] if msg.msg else ''))
        if self.has('/diagnostics'):
            for _, msg, _ in self.bag.read_messages(topics=['/diagnostics']):
                for s in msg.status:
                    if s.level >= 2:
                        diag.add(s.name)
        return lines, sorted(diag)

    def triggers(self):
        """[(t, trigger name)] of trigger firings: the supervisor's root container switching to a
        trigger's handler (edges labelled `fired` in container_structure), else /brain/...trigger...
        topics, else brain log lines saying a trigger fired."""
        names = set()
        for topic in self.find('/brain/', 'container_structure'):
            for _, msg, _ in self.bag.read_messages(topics=[topic]):
                for outcome, to in zip(getattr(msg, 'internal_outcomes', []), getattr(msg, 'outcomes_to', [])):
                    if outcome == 'fired':
                        names.add(to)
        fired = []
        if names:
            for topic in self.find('/brain/', 'container_status'):
                previous = {}
                for _, msg, t in self.bag.read_messages(topics=[topic]):
                    active = list(msg.active_states)
                    for name in active:
                        if name in names and name not in previous.get(msg.path, []):
                            fired.append((stamp_of(msg, t), name))
                    previous[msg.path] = active
            return sorted(fired)
        for topic in self.find('/brain/', 'trigger'):
            for _, msg, t in self.bag.read_messages(topics=[topic]):
                text = getattr(msg, 'name', None) or getattr(msg, 'data', None) or topic
                fired.append((stamp_of(msg, t), str(text)))
        if not fired and self.has('/rosout'):
            for _, msg, t in self.bag.read_messages(topics=['/rosout']):
                if 'brain' in msg.name and 'trigger' in msg.msg.lower() and 'fire' in msg.msg.lower():
                    fired.append((t.to_sec(), msg.msg.splitlines()[0]))
        return sorted(fired)


def errors_against_truth(estimate, truth):
    """[(t, position error [m], heading error [rad])], truth interpolated at each estimate."""
    out = []
    if len(truth) < 2:
        return out
    j = 0
    for t, x, y, a in estimate:
        while j + 1 < len(truth) and truth[j + 1][0] < t:
            j += 1
        if j + 1 >= len(truth) or t < truth[0][0]:
            continue
        (t0, x0, y0, a0), (t1, x1, y1, a1) = truth[j], truth[j + 1]
        f = 0.0 if t1 <= t0 else (t - t0) / (t1 - t0)
        tx, ty = x0 + f * (x1 - x0), y0 + f * (y1 - y0)
        ta = a0 + f * math.atan2(math.sin(a1 - a0), math.cos(a1 - a0))
        out.append((t, math.hypot(x - tx, y - ty), abs(math.atan2(math.sin(a - ta), math.cos(a - ta)))))
    return out


def report(bag_path, out_png):
    m = Match(bag_path)
    absent = []
    est_topic = '/mcl/pose' if m.has('/mcl/pose') else ('/odom' if m.has('/odom') else None)
    for topic in ('/mcl/pose', '/odom', '/sim/ground_truth', '/rosout', '/diagnostics'):
        if not m.has(topic):
            absent.append(topic)
    estimate = m.poses(est_topic) if est_topic else []
    truth = m.poses('/sim/ground_truth')
    err = errors_against_truth(estimate, truth)
    state_topic, states = m.brain_states()
    if not state_topic:
        absent.append('/brain/... (states)')
    score_topic, score = m.score()
    if score_topic is None:
        absent.append('/sim/...score...')
    error_lines, diag_bad = m.errors()
    fired = m.triggers()
    t0 = m.start

    summary = ['bag: %s' % os.path.basename(bag_path),
               'duration: %.1f s, %d topics, %d messages' % (m.end - m.start, len(m.topics),
                                                           sum(c for _, c in m.topics.values())),
               'score: %s' % ('%g (%s)' % (score, score_topic) if score_topic else 'absent'),
               'estimate: %s (%d poses)' % (est_topic or 'absent', len(estimate)),
               'truth: %s' % ('/sim/ground_truth (%d poses)' % len(truth) if truth else 'absent')]
    if err:
        pos = [e[1] for e in err]
        rms = math.sqrt(sum(p * p for p in pos) / len(pos))
        summary.append('localization error: RMS %.3f m, max %.3f m, heading max %.1f deg'
                       % (rms, max(pos), math.degrees(max(e[2] for e in err))))
    else:
        summary.append('localization error: absent (needs an estimate and /sim/ground_truth)')
    summary.append('brain states: %s' % ('%d changes on %s' % (len(states), state_topic) if states else 'absent'))
    match = m.match_status()
    if match is not None:
        summary.append('match: %s, strategy %s, %.1f s elapsed' % (match.state, match.strategy, match.elapsed))
    summary.append('errors: %d ERROR/FATAL log line(s), %d diagnostic(s) went ERROR/STALE%s'
                   % (len(error_lines), len(diag_bad), (': ' + ', '.join(diag_bad[:4])) if diag_bad else ''))
    for line in error_lines[:3]:
        summary.append('  ' + line[:90])
    summary.append('trigger firings: %d%s' % (len(fired), (' (' + ', '.join(sorted({f[1] for f in fired}))[:80] + ')')
                                              if fired else ''))
    summary.append('absent topics: %s' % (', '.join(absent) if absent else 'none'))

    fig = plt.figure(figsize=(14, 10))
    grid = fig.add_gridspec(3, 2, height_ratios=[2.2, 1, 1])
    ax = fig.add_subplot(grid[0, 0])
    length, width = m.table()
    ax.add_patch(plt.Rectangle((0, 0), length, width, facecolor='#2e7d32', alpha=0.25, edgecolor='#5d4037', lw=3))
    if truth:
        ax.plot([p[1] for p in truth], [p[2] for p in truth], '-', color='green', lw=2, label='true (/sim/ground_truth)')
    if estimate:
        ax.plot([p[1] for p in estimate], [p[2] for p in estimate], '--', color='darkorange', lw=1.5,
                label='estimated (%s)' % est_topic)
        ax.plot(estimate[0][1], estimate[0][2], 'o', color='black', label='start')
    if not truth and not estimate:
        ax.text(length / 2, width / 2, 'no trajectory in this bag', ha='center', va='center')
    ax.set_xlim(-0.2, length + 0.2)
    ax.set_ylim(-0.2, width + 0.2)
    ax.set_aspect('equal')
    ax.set_xlabel('x [m] (map)')
    ax.set_ylabel('y [m]')
    ax.set_title('trajectory on the table')
    if truth or estimate:
        ax.legend(loc='upper right', fontsize=8)

    ax = fig.add_subplot(grid[0, 1])
    ax.axis('off')
    ax.text(0.0, 1.0, '\n'.join(summary), va='top', ha='left', family='monospace', fontsize=9, wrap=True)
    ax.set_title('summary')

    ax = fig.add_subplot(grid[1, :])
    if err:
        ax.plot([e[0] - t0 for e in err], [e[1] for e in err], color='crimson', label='position error [m]')
        ax2 = ax.twinx()
        ax2.plot([e[0] - t0 for e in err], [math.degrees(e[2]) for e in err], color='steelblue', lw=0.8,
                 label='heading error [deg]')
        ax2.set_ylabel('heading error [deg]')
        ax.set_ylim(bottom=0.0, top=max(0.05, 1.1 * max(e[1] for e in err)))
        ax2.set_ylim(bottom=0.0, top=max(5.0, 1.1 * math.degrees(max(e[2] for e in err))))
        ax.legend(loc='upper left', fontsize=8)
        ax2.legend(loc='upper right', fontsize=8)
    else:
        ax.text(0.5, 0.5, 'localization error: absent (needs %s and /sim/ground_truth)' % (est_topic or '/mcl/pose'),
                ha='center', va='center', transform=ax.transAxes)
    ax.set_ylabel('position error [m]')
    ax.set_xlim(0, max(m.end - m.start, 1.0))
    ax.set_title('localization error over time')

    ax = fig.add_subplot(grid[2, :])
    if states:
        names = []
        for _, n in states:
            if n not in names:
                names.append(n)
        xs = [s[0] - t0 for s in states] + [m.end - t0]
        ys = [names.index(s[1]) for s in states]
        ax.step(xs, ys + [ys[-1]], where='post', color='purple')
        ax.set_yticks(range(len(names)))
        ax.set_yticklabels([n[-40:] for n in names], fontsize=7)
    else:
        ax.text(0.5, 0.5, 'brain states: absent', ha='center', va='center', transform=ax.transAxes)
    for t, name in fired:
        ax.axvline(t - t0, color='red', lw=0.8, alpha=0.6)
    ax.set_xlim(0, max(m.end - m.start, 1.0))
    ax.set_xlabel('match time [s]')
    ax.set_title('brain states (red lines: trigger firings)')

    fig.suptitle('match report: %s' % os.path.basename(bag_path))
    fig.tight_layout()
    fig.savefig(out_png, dpi=80)
    plt.close(fig)
    with open(os.path.splitext(out_png)[0] + '.txt', 'w') as f:
        f.write('\n'.join(summary) + '\n')
    return summary


def newest_bag():
    bags = glob.glob(os.path.expanduser('~/.ros/*.bag'))
    return max(bags, key=os.path.getmtime) if bags else None


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('bag', nargs='?', help='recorded bag (default: newest ~/.ros/*.bag)')
    parser.add_argument('-o', '--output', help='PNG to write (default: the bag with .png)')
    args = parser.parse_args()
    bag = args.bag or newest_bag()
    if not bag:
        sys.stderr.write('match_report: no bag given and none in ~/.ros (record one with record:=true)\n')
        return 2
    if not os.path.isfile(bag):
        sys.stderr.write('match_report: %s does not exist\n' % bag)
        return 2
    out = args.output or os.path.splitext(bag)[0] + '.png'
    try:
        summary = report(bag, out)
    except rosbag.ROSBagException as e:
        sys.stderr.write('match_report: cannot read %s: %s (an unfinished bag: rosbag reindex it)\n' % (bag, e))
        return 2
    print('\n'.join(summary))
    print('match report: %s' % out)
    return 0


if __name__ == '__main__':
    sys.exit(main())
