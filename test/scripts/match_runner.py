"""Runs one of the match runners (scripts/run_matches.py, scripts/run_chaos.py) for a test, the
way a team runs it from make, and returns (exit code or None on timeout, its whole output)."""
import os
import signal
import subprocess


def run_runner(cmd, timeout):
    # A session of its own: on a timeout, Ctrl-C reaches the runner and its run_match.py, which
    # stops the robot it launched (a plain kill would leave that simulation running).
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True,
                            start_new_session=True)
    try:
        output = proc.communicate(timeout=timeout)[0]
        return proc.returncode, output
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGINT)
        try:
            output = proc.communicate(timeout=90)[0]
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            output = proc.communicate()[0]
        return None, output + '\n(%s did not finish in %.0f s)' % (os.path.basename(cmd[1]), timeout)
