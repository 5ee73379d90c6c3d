"""Matches spread over a Dask distributed cluster (`make matches CLUSTER=...`, `make tune`).

A match is one job: {robot, seed, opponent kind, factor, strategy, params}. `play` runs it on a
worker: scripts/run_match.py on a ROS master, ports and temporary directory of its own
(run_match.run_one), then the row of figures and invariants from its bag (match_rows.analyse).
The row and the match's report (text and PNG) come back to the client, which writes them in
OUT/ROBOT_seed<seed>/ as a local run does; the bag stays on the worker (its path is in the row)
unless `fetch_bags`. On the local cluster the workers share this disk, so the whole folder,
bag included, is written where a run without a cluster writes it.

Without an address, a LocalCluster sized to the machine: one single-threaded worker process per
CORES_PER_MATCH cores. A match is five processes (simulator, HCL, HAL, brain, recorder): at real
time they keep more than one core busy, and at factor 0 they take what they get, so matches
crowded onto fewer cores finish later together than one after the other.

A worker that dies mid-match (its process killed, its machine gone) costs that match one retry
on another worker: the scheduler reruns a task whose worker died, up to its `allowed-failures`
(the local cluster sets 1; start a remote scheduler with DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES=1).
Every attempt logs an event on the scheduler (topic `matches`), so the client counts the retries;
a match whose workers died more often than that comes back as a row with a violation, never lost.

Workers need this workspace on their machine and its environment (`make worker CLUSTER=...`).
"""
import collections
import hashlib
import json
import logging
import os
import shutil
import socket
import tempfile
import time
import uuid

from robot_tools.matches import match_config
from robot_tools.matches import match_rows
from robot_tools.matches import run_match

EVENT_TOPIC = 'matches'
RETRIES = 1  # a match whose worker died runs once more, elsewhere
WORKER_WAIT = 60.0  # [s] for a remote scheduler's first worker
CORES_PER_MATCH = 2

Job = collections.namedtuple('Job', 'robot seed opponent factor strategy params out fetch_bags shared_disk tag')
Job.__new__.__defaults__ = ('',)  # tag: set by run_jobs, one per run


def local_cluster(workers=None):
    """A LocalCluster of `workers` single-threaded worker processes (default: one per CORES_PER_MATCH cores)."""
    import dask
    from distributed import LocalCluster
    dask.config.set({'distributed.scheduler.allowed-failures': RETRIES})
    n = workers or max(1, (os.cpu_count() or 1) // CORES_PER_MATCH)
    return LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
                        silence_logs=logging.ERROR, scheduler_port=0)


def connect(address=None, workers=None):
    """(client, cluster or None): to the scheduler at `address` (tcp://HOST:8786), or to a new
    local cluster. The workers import this module by name (robot_tools, from the sourced workspace)."""
    from distributed import Client
    if address:
        client = Client(address, timeout=30)
        try:
            client.wait_for_workers(1, timeout=WORKER_WAIT)
        except Exception:
            client.close()
            raise SystemExit('matches: the scheduler at %s has no worker after %.0f s (make worker CLUSTER=%s on '
                             'the machines that play)' % (address, WORKER_WAIT, address))
        return client, None
    cluster = local_cluster(workers)
    client = Client(cluster)
    try:
        client.wait_for_workers(len(cluster.workers), timeout=WORKER_WAIT)
    except Exception:
        client.close()
        cluster.close()
        raise SystemExit('matches: the local cluster\'s workers did not start within %.0f s' % WORKER_WAIT)
    return client, cluster


def worker_count(client):
    return len(client.scheduler_info().get('workers', {}))


def _log_attempt(job):
    try:
        from distributed import get_worker
        worker = get_worker()
        worker.log_event(EVENT_TOPIC, {'seed': job.seed, 'key': key_of(job), 'worker': worker.address,
                                       'host': socket.gethostname()})
    except Exception:  # not on a worker (a direct call): nothing to count
        pass


def key_of(job):
    """The task's key: one per run, match, parameter set and output folder, so a retry is the same task (and a
    scheduler that served earlier runs does not count their attempts as this run's)."""
    params = hashlib.sha1(json.dumps([job.out, job.params], sort_keys=True).encode()).hexdigest()[:10]
    return 'match-%s-seed%d-%s-%s' % (job.robot, job.seed, params, job.tag)


def play(job, index=1, n=1):
    """One match on this machine (a worker): its row, as a dict, and its report files."""
    _log_attempt(job)
    config = match_config.robot_config(job.robot)
    overlay_params = match_config.match_overlay(match_config.opponent_params(job.opponent, config), job.params)
    folder = os.path.join(job.out, '%s_seed%d' % (job.robot, job.seed)) if job.shared_disk else \
        tempfile.mkdtemp(prefix='match_%s_seed%d_' % (job.robot, job.seed))
    os.makedirs(folder, exist_ok=True)
    overlay = match_config.write_overlay(folder, overlay_params)
    t0 = time.monotonic()
    rc = run_match.run_one(job.robot, job.seed, job.factor, folder, overlay, job.strategy, index, n)
    row = match_rows.analyse(job.seed, job.opponent, folder, job.robot, match_config.merged(config, overlay_params),
                              rc, time.monotonic() - t0)
    files = {}
    if not job.shared_disk:
        for name in sorted(os.listdir(folder)):
            path = os.path.join(folder, name)
            if os.path.isfile(path) and (job.fetch_bags or not name.endswith('.bag')):
                with open(path, 'rb') as f:
                    files[name] = f.read()
        if job.fetch_bags:
            shutil.rmtree(folder, ignore_errors=True)
    out = row._asdict()
    out['folder'] = folder if job.shared_disk or not job.fetch_bags else None
    out['host'] = socket.gethostname()
    return out, files


def lost_row(job, why):
    """The row of a match that never came back: every figure unknown, one violation."""
    fields = {f: None for f in match_rows.MatchRow._fields}
    fields.update(seed=job.seed, opponent=job.opponent, folder=None, wall=None, errors=[], violations=[why])
    return match_rows.MatchRow(**fields)


def run_jobs(client, jobs, on_done=None):
    """Every job on the cluster, as they finish: returns ([MatchRow] in the jobs' order, retries).
    `on_done(k, row, retries_so_far)` is called as each match comes back. A row's folder is
    where its files are on this machine (the worker's bag path is said in `remote_bag`)."""
    from distributed import as_completed
    tag = uuid.uuid4().hex[:12]
    jobs = [job._replace(tag=tag) for job in jobs]
    keys = {key_of(job) for job in jobs}
    futures = {client.submit(play, job, k + 1, len(jobs), key=key_of(job), pure=False): k for k, job in enumerate(jobs)}
    rows = [None] * len(jobs)
    for future in as_completed(list(futures)):
        k = futures[future]
        job = jobs[k]
        try:
            fields, files = future.result()
        except Exception as e:  # KilledWorker: its workers died more than RETRIES times
            rows[k] = lost_row(job, 'lost: %s: %s' % (type(e).__name__, str(e).splitlines()[0][:200] if str(e) else ''))
        else:
            host, folder = fields.pop('host'), fields['folder']
            if files:  # a remote worker: the report (and the bag if asked) come home
                local = os.path.join(job.out, '%s_seed%d' % (job.robot, job.seed))
                os.makedirs(local, exist_ok=True)
                for name, data in files.items():
                    with open(os.path.join(local, name), 'wb') as f:
                        f.write(data)
                if folder and not job.fetch_bags:
                    with open(os.path.join(local, 'remote_bag.txt'), 'w') as f:
                        f.write('%s:%s\n' % (host, os.path.join(folder, '%s_match.bag' % job.robot)))
                fields['folder'] = local
            rows[k] = match_rows.MatchRow(**fields)
        if on_done:
            on_done(k, rows[k], retries(client, keys))
    return rows, retries(client, keys)


def retries(client, keys):
    """Retries so far among these tasks: attempts logged beyond one per key."""
    seen = collections.Counter(msg.get('key') for _, msg in client.get_events(EVENT_TOPIC) if msg.get('key') in keys)
    return sum(c - 1 for c in seen.values())
