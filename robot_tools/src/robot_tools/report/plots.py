"""The match report's PNG: the fixed layout (draw) and its panels, the table with paths, zones,
elements and goals, and the timelines of score, localization error, driver goals and brain states,
and the wrapped summary text. Drawing only: report() computes every figure and hands them over."""
import math
import os
import textwrap

import matplotlib
matplotlib.use('Agg')  # headless: no display needed
import matplotlib.pyplot as plt

from robot_tools.report.match_bag import DRIVER_ACTIONS

STATUS_COLOURS = {'SUCCEEDED': '#2e7d32', 'ABORTED': '#d32f2f', 'PREEMPTED': '#ef6c00', 'REJECTED': '#6a1b9a',
                  'RECALLED': '#8d6e63', 'LOST': '#000000', 'no result': '#9e9e9e'}
X_LABEL = 'match time [s] (0 = start signal)'


def element_colour(kind):
    """The simulator's marker colour of an element kind (robot_sim ros_world_io.cpp)."""
    for word, colour in (('red', '#e53935'), ('blue', '#1e4ee6'), ('green', '#1db233'), ('white', '#f2f2f2'),
                         ('column', '#f2d98c')):
        if word in kind:
            return colour
    return '#cccccc'



def wrap(lines, width):
    """The summary wrapped to `width` characters; continuation lines keep the indentation."""
    out = []
    for line in lines:
        indent = len(line) - len(line.lstrip(' '))
        out.extend(textwrap.wrap(line, width, subsequent_indent=' ' * (indent + 4), break_long_words=True,
                                 break_on_hyphens=False) or [''])
    return out


def draw(m, bag_path, out_png, v):
    """The PNG: a fixed layout (the table keeps its size and aspect whatever the bag's length)."""
    t0, length, width = v['t0'], v['length'], v['width']
    fig_w, fig_h, dpi = 20.0, 15.0, 80
    fig = plt.figure(figsize=(fig_w, fig_h))
    fig.suptitle('match report: %s' % os.path.basename(bag_path), fontsize=15, x=0.01, y=0.995, ha='left',
                 weight='bold')
    left_w = 0.60  # of the figure: the table and the timelines; the text panel right of it
    margin = 0.2
    # The table: equal aspect, as wide as the left column, its height from the table's dimensions.
    tab_w_in = left_w * fig_w - 1.0
    tab_h_in = min(6.0, tab_w_in * (width + 2 * margin) / (length + 2 * margin))
    tab_w_in = tab_h_in * (length + 2 * margin) / (width + 2 * margin)
    tab_bottom = 1.0 - 0.045 - tab_h_in / fig_h
    ax = fig.add_axes([0.04, tab_bottom, tab_w_in / fig_w, tab_h_in / fig_h])
    draw_table(ax, v)

    # Timelines below the table, sharing the match time axis.
    x_lo = min(0.0, m.start - t0) if m.topics else 0.0
    x_hi = max(m.end - t0, x_lo + 1.0)
    lanes = [('score', 1.0), ('localization', 0.8), ('goals', 0.7), ('states', 2.0)]
    top, bottom, gap = tab_bottom - 0.065, 0.04, 0.027
    total = sum(h for _, h in lanes)
    avail = top - bottom - gap * (len(lanes) - 1)
    y = top
    axes = {}
    for name, h in lanes:
        hh = avail * h / total
        axes[name] = fig.add_axes([0.105, y - hh, left_w - 0.15, hh], sharex=axes.get('score'))
        y -= hh + gap
    draw_score(axes['score'], v)
    draw_localization(axes['localization'], v)
    draw_goals(axes['goals'], v)
    draw_states(axes['states'], v, m.end)
    for name, a in axes.items():
        if x_lo < 0:
            a.axvspan(x_lo, 0.0, color='#bbbbbb', alpha=0.25, lw=0)
        for t, trig in v['fired']:
            a.axvline(t - t0, color='red', lw=0.9, alpha=0.7)
        if name != 'states':
            plt.setp(a.get_xticklabels(), visible=False)
    for t, trig in v['fired']:
        axes['states'].annotate(trig, (t - t0, 0.03), xycoords=('data', 'axes fraction'), xytext=(-2, 0),
                                textcoords='offset points', fontsize=7, color='red', rotation=90, va='bottom',
                                ha='right')
    axes['states'].set_xlim(x_lo, x_hi)
    axes['states'].set_xlabel(X_LABEL if v['t_signal'] is not None else
                              'match time [s] (no start signal in this bag: 0 = bag start)')

    # The text panel: wrapped to its width, cut (with a note) at its height.
    tx = fig.add_axes([left_w + 0.005, 0.02, 1.0 - left_w - 0.01, 0.95])
    tx.axis('off')
    tx.set_title('summary', loc='left', fontsize=11)
    fontsize = 8.5
    chars = int((1.0 - left_w - 0.02) * fig_w * 72 / (0.62 * fontsize)) - 2  # monospace: 0.6 em a character
    rows = int(0.95 * fig_h * 72 / (1.22 * fontsize)) - 2
    lines = wrap(v['summary'], chars)
    if len(lines) > rows:
        lines = lines[:rows - 1] + ['... (%d more lines in %s)' % (len(lines) - rows + 1,
                                                                os.path.basename(os.path.splitext(out_png)[0] + '.txt'))]
    tx.text(0.0, 1.0, '\n'.join(lines), va='top', ha='left', family='monospace', fontsize=fontsize,
            transform=tx.transAxes, linespacing=1.15)
    fig.savefig(out_png, dpi=dpi)
    plt.close(fig)


def draw_table(ax, v):
    length, width = v['length'], v['width']
    ax.add_patch(plt.Rectangle((0, 0), length, width, facecolor='#2e7d32', alpha=0.15, edgecolor='#5d4037', lw=3))
    for ns in ('start_zones', 'score_zones'):
        for i, (x, y, sx, sy, rgb) in enumerate(v['zones'].get(ns, [])):
            if ns == 'start_zones':  # in its team's colour
                style = dict(facecolor=rgb + (0.35,), edgecolor=rgb, lw=1.5, ls='-', label='start zone')
            else:  # the markers draw them pale (white): here one visible style
                style = dict(facecolor=(1.0, 0.76, 0.03, 0.30), edgecolor='#b8860b', lw=1.5, ls='--', hatch='//',
                             label='score zone')
            if i:
                style['label'] = None
            ax.add_patch(plt.Rectangle((x, y), sx, sy, **style))
    start, end = v['elements_start'], v['elements_end']
    for i, (kind, x, y, r, _) in enumerate(start):
        ax.add_patch(plt.Circle((x, y), max(r, 0.01), facecolor='none', edgecolor=element_colour(kind), lw=1.2,
                                ls=':', label='element at start' if i == 0 else None))
    for i, (kind, x, y, r, carried) in enumerate(end):
        ax.add_patch(plt.Circle((x, y), max(r, 0.01), facecolor=element_colour(kind), edgecolor='black', lw=0.6,
                                alpha=0.9, label='element at end' if i == 0 else None))
        if carried:
            ax.plot(x, y, 'x', color='black', ms=6)
        if i < len(start) and math.hypot(x - start[i][1], y - start[i][2]) > 0.02:
            ax.annotate('', (x, y), (start[i][1], start[i][2]),
                        arrowprops=dict(arrowstyle='->', color='#555555', lw=0.8, ls='--'))
    opp = v['opponent']
    if opp:
        ax.plot([p[1] for p in opp], [p[2] for p in opp], '-', color='#8e24aa', lw=1.3, alpha=0.8,
                label='opponent (/sim/opponent)')
        ax.plot(opp[0][1], opp[0][2], 's', color='#8e24aa', ms=6)
        ax.plot(opp[-1][1], opp[-1][2], 'D', color='#8e24aa', ms=6)
    truth, estimate = v['truth'], v['estimate']
    if truth:
        ax.plot([p[1] for p in truth], [p[2] for p in truth], '-', color='#0d47a1', lw=2, label='ours, true')
    if estimate:
        ax.plot([p[1] for p in estimate], [p[2] for p in estimate], '--', color='darkorange', lw=1.3,
                label='ours, estimated (%s)' % v['est_topic'])
    path = truth or estimate
    if path:
        ax.plot(path[0][1], path[0][2], 'o', color='black', ms=7, label='ours: start (o), end (D)')
        ax.plot(path[-1][1], path[-1][2], 'D', color='black', ms=6)
    arrow = 0.12
    shown = set()
    for g in v['goals']:
        if g['action'] != 'goto':
            continue
        goal, colour = g['goal'], STATUS_COLOURS.get(g['status'], '#9e9e9e')
        label = 'goto %s' % g['status'].lower() if g['status'] not in shown else None
        shown.add(g['status'])
        ax.annotate('', (goal.x + arrow * math.cos(goal.angle), goal.y + arrow * math.sin(goal.angle)),
                    (goal.x, goal.y), arrowprops=dict(arrowstyle='-|>', color=colour, lw=1.8, mutation_scale=12))
        ax.plot(goal.x, goal.y, '.', color=colour, ms=7, label=label)
        if g['status'] in ('ABORTED', 'REJECTED', 'LOST'):
            ax.annotate('#%d' % g['n'], (goal.x, goal.y), xytext=(4, -10), textcoords='offset points',
                        fontsize=8, color=colour, weight='bold')
    if not path and not opp:
        ax.text(length / 2, width / 2, 'no trajectory in this bag', ha='center', va='center')
    ax.set_xlim(-0.2, length + 0.2)
    ax.set_ylim(-0.2, width + 0.2)
    ax.set_aspect('equal', adjustable='box')
    ax.set_xlabel('x [m] (map)')
    ax.set_ylabel('y [m]')
    ax.set_title('the table: paths, zones, elements (dotted: start, filled: end), goto goals (#: aborted)',
                 fontsize=10)
    handles, labels = ax.get_legend_handles_labels()
    if handles:
        ax.legend(handles, labels, loc='upper left', bbox_to_anchor=(1.01, 1.0), fontsize=8, borderaxespad=0.0)


def draw_score(ax, v):
    t0, series, events = v['t0'], list(v['score_series']), v['events']
    if series and v['m'].end > series[-1][0]:
        series.append((v['m'].end,) + tuple(series[-1][1:]))  # the last score holds to the bag's end
    if series:
        ts = [s[0] - t0 for s in series]
        if v['attributed']:
            ax.step(ts, [s[1] for s in series], where='post', color='#1565c0', lw=2, label='ours')
            ax.step(ts, [s[2] for s in series], where='post', color='#8e24aa', lw=2, label='opponent')
        else:
            ax.step(ts, [s[1] for s in series], where='post', color='#1565c0', lw=2,
                    label='score (%s, no attribution)' % v['score_topic'])
    elif events:
        for team, colour in (('ours', '#1565c0'), ('opponent', '#8e24aa')):
            ts, total, ys = [0.0], 0, [0]
            for e in events:
                if e[1] == team:
                    total += e[2]
                    ts.append(e[0])
                    ys.append(total)
            ax.step(ts, ys, where='post', color=colour, lw=2, label=team + ' (from score events)')
    for e in events:
        colour = '#1565c0' if e[1] == 'ours' else '#8e24aa'
        ax.plot(e[0], 0, '^' if e[2] > 0 else 'v', color=colour, ms=6, clip_on=False)
    if series or events:
        ax.legend(loc='upper left', fontsize=8)
        ax.set_ylim(bottom=min(0, ax.get_ylim()[0]))
    else:
        ax.text(0.5, 0.5, 'score: absent', ha='center', va='center', transform=ax.transAxes)
    ax.set_ylabel('points')
    ax.set_title('score (triangles: score events; red lines: trigger firings)', fontsize=10, loc='left')
    ax.grid(alpha=0.3)


def draw_localization(ax, v):
    err, t0 = v['err'], v['t0']
    if err:
        ax.plot([e[0] - t0 for e in err], [e[1] for e in err], color='crimson', label='position error [m]')
        ax2 = ax.twinx()
        ax2.plot([e[0] - t0 for e in err], [math.degrees(e[2]) for e in err], color='steelblue', lw=0.8,
                 label='heading error [deg]')
        ax2.set_ylabel('heading [deg]')
        ax.set_ylim(bottom=0.0, top=max(0.05, 1.1 * max(e[1] for e in err)))
        ax2.set_ylim(bottom=0.0, top=max(5.0, 1.1 * math.degrees(max(e[2] for e in err))))
        ax.legend(loc='upper left', fontsize=8)
        ax2.legend(loc='upper right', fontsize=8)
    else:
        ax.text(0.5, 0.5, 'localization error: absent (needs %s and /sim/ground_truth)'
                % (v['est_topic'] or '/mcl/pose'), ha='center', va='center', transform=ax.transAxes)
    ax.set_ylabel('position [m]')
    ax.set_title('localization error (estimate vs truth)', fontsize=10, loc='left')
    ax.grid(alpha=0.3)


def draw_goals(ax, v):
    goals, t0, end = v['goals'], v['t0'], v['m'].end
    actions = [a for a in DRIVER_ACTIONS if any(g['action'] == a for g in goals)]
    for g in goals:
        row = actions.index(g['action'])
        t_end = g['t_end'] if g['t_end'] is not None else end
        colour = STATUS_COLOURS.get(g['status'], '#9e9e9e')
        ax.broken_barh([(g['t_sent'] - t0, max(t_end - g['t_sent'], 0.05))], (row - 0.35, 0.7),
                       facecolors=colour, edgecolors='white', lw=0.5)
        if g['status'] in ('ABORTED', 'REJECTED', 'LOST'):
            ax.text(t_end - t0, row + 0.38, '#%d' % g['n'], fontsize=7, color=colour, weight='bold', va='bottom')
    if goals:
        ax.set_yticks(range(len(actions)))
        ax.set_yticklabels(actions, fontsize=8)
        ax.set_ylim(-0.6, len(actions) - 0.4 + 0.3)
        used = []
        for g in goals:
            if g['status'] not in used:
                used.append(g['status'])
        for s in used:
            ax.plot([], [], 's', color=STATUS_COLOURS.get(s, '#9e9e9e'), label=s.lower())
        ax.legend(loc='upper left', bbox_to_anchor=(1.005, 1.0), fontsize=7, borderaxespad=0.0)
    else:
        ax.set_yticks([])
        ax.text(0.5, 0.5, 'driver goals: absent', ha='center', va='center', transform=ax.transAxes)
    ax.set_title('driver goals by result', fontsize=10, loc='left')
    ax.grid(alpha=0.3, axis='x')


def draw_states(ax, v, bag_end):
    states, t0 = v['states'], v['t0']
    depth = None
    if states:
        # A long match visits many state chains: show them as deep as 20 rows allow.
        deepest = max(n.count('/') + 1 for _, n in states)
        for depth in range(deepest, 0, -1):
            if len({'/'.join(n.split('/')[:depth]) for _, n in states}) <= 20:
                break
        states = [(t, '/'.join(n.split('/')[:depth])) for t, n in states]
        if depth == deepest:
            depth = None
        names = []
        for _, n in states:
            if n not in names:
                names.append(n)
        xs = [s[0] - t0 for s in states] + [bag_end - t0]
        ys = [names.index(s[1]) for s in states]
        ax.step(xs, ys + [ys[-1]], where='post', color='purple')
        ax.set_yticks(range(len(names)))
        size = 7
        ax.set_yticklabels([n if len(n) <= 36 else '...' + n[-33:] for n in names], fontsize=size)
    else:
        ax.set_yticks([])
        ax.text(0.5, 0.5, 'brain states: absent', ha='center', va='center', transform=ax.transAxes)
    ax.set_title('brain states%s (red: trigger firings)' % (' (chains cut to %d levels)' % depth if depth else ''),
                 fontsize=10, loc='left')
    ax.grid(alpha=0.3, axis='x')
