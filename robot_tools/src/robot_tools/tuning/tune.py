"""`make tune`: an Optuna study of a robot's parameters, each trial a set of simulated matches.

    scripts/tune.py ROBOT [--trials 50] [--seeds 5] [--seed 1] [--holdout H] [--holdout-seed K] [--factor 0]
                    [--cluster tcp://HOST:8786] [--workers W] [--storage URL] [--study NAME]
                    [--out DIR] [--match-duration S]

The parameters and their ranges are config/tune/ROBOT.yaml's (`parameters:`). A trial is one
set of values from Optuna's TPE sampler, written as an overlay of config/ROBOT.yaml and played
in --seeds matches: seeds SEED .. SEED+seeds-1, opponents cycling as in `make matches`, the same
for every trial. As many trials run at once as the cluster has workers for their matches. Its value (robot_tools.tuning.objective) is our mean score less penalties for
contacts with the opponent and for broken invariants. The matches run on the Dask cluster
(robot_tools.matches.cluster: --cluster, else a local one).

The study lives in --storage (default sqlite:///OUT/ROBOT_study.db) under --study (default
ROBOT): stopped, it resumes where it was; several machines running this with one storage URL
(a database they all reach) work on one study. --trials is the study's total: a resumed study
plays only the trials it still lacks. A new study's first trial is the shipped config's values.

At the end: OUT/ROBOT_best.yaml (the best trial's values as an overlay: roslaunch ...
overlay:=OUT/ROBOT_best.yaml), OUT/ROBOT_tune.png (optimisation history and parameter
importances), and the verdict: the best overlay and the shipped config each play --holdout
matches on seeds no trial saw (SEED+HOLDOUT_OFFSET ..., or --holdout-seed K ...: a fresh held-out
set declared before a second look, so that a verdict is never settled by adding seeds to the first
one until it clears 0), same opponents for both, and the last line is
    trials T best_score B baseline_score S improvement D ci95 [L, H]
Each arm's matches are tabled as `make matches` tables them (OUT/holdout_best/ROBOT_matches.txt,
OUT/holdout_shipped/...): `scripts/scoreboard.py --judge ROBOT=OUT/holdout_best` judges them.
B and S: our mean score on the held-out seeds with the best overlay and with the shipped config;
D = B - S and its 95 % interval (paired t). An interval that contains 0 is no improvement.
"""
import argparse
import io
import os
import sys
import time

import yaml

from robot_tools.paths import ROOT
from robot_tools.matches import cluster as match_cluster
from robot_tools.matches import match_config
from robot_tools.matches import match_rows
from robot_tools.tuning import objective as tune_objective

HOLDOUT_OFFSET = 100000  # held-out seeds start here past --seed: no trial plays them


def log(msg):
    print('tune: ' + msg, flush=True)


# ---- the declared parameters -------------------------------------------------------------------

def load_space(robot):
    """(parameters, objective weights) of config/tune/ROBOT.yaml, checked: a clear error per
    malformed entry, naming it."""
    path = os.path.join(ROOT, 'config', 'tune', robot + '.yaml')
    if not os.path.exists(path):
        sys.exit('tune: no config/tune/%s.yaml: declare the parameters to tune there (see config/tune/)' % robot)
    with open(path) as f:
        spec = yaml.safe_load(f) or {}
    params = spec.get('parameters') or []
    if not isinstance(params, list) or not params:
        sys.exit('tune: %s: `parameters` must be a non-empty list' % path)
    config = match_config.robot_config(robot)
    for p in params:
        name = p.get('name') if isinstance(p, dict) else None
        if not name:
            sys.exit('tune: %s: each parameter needs a `name`: %r' % (path, p))
        if lookup(config, name) is KeyError:
            sys.exit('tune: %s: %s is not a parameter of config/%s.yaml' % (path, name, robot))
        if 'choices' in p:
            if not isinstance(p['choices'], dict) or not p['choices']:
                sys.exit('tune: %s: %s: `choices` must map labels to values' % (path, name))
        elif not all(isinstance(p.get(k), (int, float)) for k in ('low', 'high')) or p['low'] >= p['high']:
            sys.exit('tune: %s: %s needs numbers low < high, or choices' % (path, name))
    weights = dict(tune_objective.DEFAULTS, **(spec.get('objective') or {}))
    return params, weights


def lookup(config, name):
    node = config
    for key in name.strip('/').split('/'):
        if not isinstance(node, dict) or key not in node:
            return KeyError
        node = node[key]
    return node


def overlay_of(values):
    """{'hal': {'driver': ...}} of {'hal/driver/...': value}."""
    out = {}
    for name, value in values.items():
        node = out
        keys = name.strip('/').split('/')
        for key in keys[:-1]:
            node = node.setdefault(key, {})
        node[keys[-1]] = value
    return out


def suggest(trial, params):
    """The trial's values: {name: value}, a choice as its value (its label is the trial's param)."""
    values = {}
    for p in params:
        name = p['name']
        if 'choices' in p:
            label = trial.suggest_categorical(name, sorted(p['choices']))
            values[name] = p['choices'][label]
        elif isinstance(p['low'], int) and isinstance(p['high'], int) and not p.get('log'):
            values[name] = trial.suggest_int(name, p['low'], p['high'], step=int(p.get('step', 1)))
        else:
            values[name] = trial.suggest_float(name, float(p['low']), float(p['high']), log=bool(p.get('log')),
                                               step=p.get('step'))
    return values


def shipped_point(params, config):
    """The shipped config's values as a trial (labels for choices), or None when one lies outside
    its declared range (the study then starts from the sampler alone)."""
    point = {}
    for p in params:
        value = lookup(config, p['name'])
        if 'choices' in p:
            labels = [label for label, v in p['choices'].items() if v == value]
            if not labels:
                return None
            point[p['name']] = labels[0]
        elif not (p['low'] <= value <= p['high']):
            return None
        else:
            point[p['name']] = value
    return point


def values_of(params, trial_params):
    """{name: value} of a finished trial's params (labels turned back into their values)."""
    return {p['name']: (p['choices'][trial_params[p['name']]] if 'choices' in p else trial_params[p['name']])
            for p in params}


# ---- matches -----------------------------------------------------------------------------------

def held_out_seeds(seed, seeds, holdout, holdout_seed=None):
    """The verdict's seeds: HOLDOUT matches from HOLDOUT_SEED (default SEED+HOLDOUT_OFFSET). A
    ValueError if one of them is a seed the trials play."""
    first = seed + HOLDOUT_OFFSET if holdout_seed is None else holdout_seed
    held_out = list(range(first, first + holdout))
    played = set(range(seed, seed + seeds))
    if played.intersection(held_out):
        raise ValueError('held-out seeds %d..%d overlap the trials\' seeds %d..%d' % (
            first, first + holdout - 1, seed, seed + seeds - 1))
    return held_out


def write_matches_table(folder, robot, rows, factor):
    """One arm of the verdict as `make matches` writes its table (FOLDER/ROBOT_matches.txt), so
    `make play`'s judge (scripts/scoreboard.py --judge ROBOT=FOLDER) reads its stalls and idle."""
    lines = match_rows.summary_lines(rows, sum(r.wall or 0.0 for r in rows), factor)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, '%s_matches.txt' % robot), 'w') as f:
        f.write('\n'.join(lines) + '\n')


def jobs_for(args, seeds, params, out):
    """One match per seed with these parameters, opponents cycling as in `make matches`."""
    return [match_cluster.Job(robot=args.robot, seed=s, opponent=match_config.OPPONENTS[k % len(match_config.OPPONENTS)],
                              factor=args.factor, strategy=None, params=params, out=out, fetch_bags=False,
                              shared_disk=not args.cluster) for k, s in enumerate(seeds)]


def figure(study, path):
    """History and importances side by side, one PNG (Optuna's matplotlib plots)."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    import optuna.visualization.matplotlib as ovm
    from PIL import Image
    images = []
    for name, plot in (('history', ovm.plot_optimization_history), ('importances', ovm.plot_param_importances)):
        try:
            ax = plot(study)
            fig = ax.figure
        except Exception as e:  # importances need two finished trials that differ
            fig, ax = plt.subplots(figsize=(6.4, 4.8))
            ax.text(0.5, 0.5, '%s: not enough trials yet\n(%s)' % (name, str(e).splitlines()[0][:80] if str(e) else
                                                                  type(e).__name__), ha='center', va='center')
            ax.set_axis_off()
        fig.set_size_inches(6.4, 4.8)
        fig.tight_layout()
        buf = io.BytesIO()
        fig.savefig(buf, dpi=90, format='png')
        plt.close(fig)
        images.append(Image.open(io.BytesIO(buf.getvalue())).convert('RGB'))
    width, height = sum(i.width for i in images), max(i.height for i in images)
    sheet = Image.new('RGB', (width, height), 'white')
    x = 0
    for image in images:
        sheet.paste(image, (x, 0))
        x += image.width
    sheet.save(path)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('robot')
    ap.add_argument('--trials', type=int, default=50, help="the study's total number of finished trials")
    ap.add_argument('--seeds', type=int, default=5, help='matches per trial (seeds SEED ..)')
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--holdout', type=int, default=None, help='held-out matches per side of the verdict '
                    '(default: max(seeds, 2); 0: no verdict, the closing line says nan)')
    ap.add_argument('--holdout-seed', type=int, default=None,
                    help='first held-out seed (default: SEED+%d); it must not be one a trial plays' % HOLDOUT_OFFSET)
    ap.add_argument('--factor', type=float, default=0.0, help='real_time_factor (0: as fast as the machine goes)')
    ap.add_argument('--cluster', default=None, help='Dask scheduler address (default: a local cluster)')
    ap.add_argument('--workers', type=int, default=None, help='local cluster size (default: one worker per two cores)')
    ap.add_argument('--out', default=os.path.join(ROOT, 'report', 'tune'))
    ap.add_argument('--storage', default=None, help='Optuna storage URL (default: sqlite:///OUT/ROBOT_study.db)')
    ap.add_argument('--study', default=None, help='study name (default: ROBOT)')
    ap.add_argument('--match-duration', type=float, default=None,
                    help='[s] shorter matches for a quick check of the machinery (default: the config\'s)')
    args = ap.parse_args()
    for name in ('trials', 'seeds'):
        if getattr(args, name) < 1:
            sys.exit('tune: --%s = %d: must be at least 1' % (name, getattr(args, name)))
    if not os.path.exists(os.path.join(ROOT, 'launch', args.robot + '.launch')):
        sys.exit('tune: ROBOT=%s: no launch/%s.launch' % (args.robot, args.robot))
    params, weights = load_space(args.robot)
    config = match_config.robot_config(args.robot)
    holdout = max(args.seeds, 2) if args.holdout is None else args.holdout
    if holdout < 0:
        sys.exit('tune: --holdout = %d: must be 0 (no verdict) or more' % holdout)
    try:
        held_out = held_out_seeds(args.seed, args.seeds, holdout, args.holdout_seed)
    except ValueError as e:
        sys.exit('tune: --holdout-seed %s: %s' % (args.holdout_seed, e))
    os.makedirs(args.out, exist_ok=True)

    import optuna
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    storage = args.storage or 'sqlite:///%s' % os.path.abspath(os.path.join(args.out, args.robot + '_study.db'))
    study = optuna.create_study(study_name=args.study or args.robot, storage=storage, direction='maximize',
                                load_if_exists=True, sampler=optuna.samplers.TPESampler(seed=args.seed))
    finished = lambda: [t for t in study.trials if t.state == optuna.trial.TrialState.COMPLETE]  # noqa: E731
    if not study.trials:
        point = shipped_point(params, config)
        if point is not None:
            study.enqueue_trial(point)
    log('study %s in %s: %d finished trial(s), %d to go; %d match(es) each' % (
        study.study_name, storage, len(finished()), max(0, args.trials - len(finished())), args.seeds))

    began = time.monotonic()
    client, cluster = match_cluster.connect(args.cluster, args.workers)
    retried = 0
    try:
        log('%d worker(s) on %s' % (match_cluster.worker_count(client), args.cluster or 'a local cluster'))
        seeds = [args.seed + k for k in range(args.seeds)]
        # As many trials at once as the cluster has workers for their matches (at least one).
        batch = max(1, match_cluster.worker_count(client) // args.seeds)
        while len(finished()) < args.trials:
            trials = [study.ask() for _ in range(min(batch, args.trials - len(finished())))]
            values = [suggest(trial, params) for trial in trials]
            jobs = []
            for trial, v in zip(trials, values):
                jobs += jobs_for(args, seeds, match_config.with_duration(overlay_of(v), args.match_duration),
                                 os.path.join(args.out, 'trial%04d' % trial.number))
            rows, r = match_cluster.run_jobs(client, jobs)
            retried += r
            for k, trial in enumerate(trials):
                mine = rows[k * len(seeds):(k + 1) * len(seeds)]
                value = tune_objective.trial_value(mine, weights)
                study.tell(trial, value)
                broken = [row.violations[0] for row in mine if row.violations]
                log('trial %d: value %.2f (scores %s, contacts %s%s) %s' % (
                    trial.number, value, [row.ours for row in mine], [row.contacts for row in mine],
                    ', %d broken, first: %s' % (len(broken), broken[0]) if broken else '',
                    ' '.join('%s=%s' % (name.split('/')[-1], trial.params[name]) for name in sorted(trial.params))))
        best = study.best_trial
        best_values = values_of(params, best.params)
        best_path = os.path.join(args.out, args.robot + '_best.yaml')
        with open(best_path, 'w') as f:
            f.write('# scripts/tune.py: the best of %d trials of study %s (value %.2f over seeds %d..%d); an overlay\n'
                    '# of config/%s.yaml: roslaunch robot_description %s.launch overlay:=%s\n' % (
                        len(finished()), study.study_name, best.value, args.seed, args.seed + args.seeds - 1,
                        args.robot, args.robot, os.path.abspath(best_path)))
            yaml.safe_dump(overlay_of(best_values), f, default_flow_style=False)
        png = os.path.join(args.out, args.robot + '_tune.png')
        figure(study, png)
        log('best trial %d: value %.2f; overlay %s; figure %s' % (best.number, best.value, best_path, png))

        tuned, shipped = [], []
        if holdout:
            log('verdict: the best overlay and the shipped config on held-out seeds %d..%d' % (held_out[0], held_out[-1]))
            best_overlay = match_config.with_duration(overlay_of(best_values), args.match_duration)
            rows, r = match_cluster.run_jobs(
                client, jobs_for(args, held_out, best_overlay, os.path.join(args.out, 'holdout_best'))
                + jobs_for(args, held_out, match_config.with_duration({}, args.match_duration),
                           os.path.join(args.out, 'holdout_shipped')))
            tuned, shipped = rows[:holdout], rows[holdout:]
            retried += r
            for arm, arm_rows in (('holdout_best', tuned), ('holdout_shipped', shipped)):
                write_matches_table(os.path.join(args.out, arm), args.robot, arm_rows, args.factor)
        else:
            log('no verdict (--holdout 0)')
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    for name, rows in (('best', tuned), ('shipped', shipped)):
        for row in rows:
            log('held-out %s seed %d (%s): ours %s, opponent %s%s' % (
                name, row.seed, row.opponent, row.ours, row.theirs,
                ', broken: %s' % row.violations[0] if row.violations else ''))
    nan = float('nan')
    b, s, d, low, high = tune_objective.paired_verdict(tuned, shipped) if holdout else (nan,) * 5
    log('%d retries; %.0f s wall' % (retried, time.monotonic() - began))
    print(tune_objective.closing_line(len(finished()), b, s, d, low, high), flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
