#!/usr/bin/env bash
# Runs the tests and prints one summary. Exits non-zero on any failure or error. Called with the
# workspace sourced:
#   run_tests.sh          every test (gtest, nosetests, fuzz, rostest, the SocketCAN VM, the
#                         recipes of docs/adding.md): `make test`
#   run_tests.sh --quick  the tier without a simulation or a ROS master: catkin_lint, gtests,
#                         nosetests and fuzz targets (minutes after the build): `make check`
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
quick=0
[ "${1:-}" = "--quick" ] && quick=1
rm -rf build/test_results
echo "== catkin_lint"
lint_out=$(catkin_lint -W1 src 2>&1); lint_rc=$?
echo "$lint_out" | tail -n 20
lint_problems=$(echo "$lint_out" | grep -cE 'error:|warning:|cannot lint' || true)  # a package it could not read is a problem too

# Test binaries build in parallel; the tests run side by side within a CPU budget
# (scripts/test_pool.py says how; TEST_JOBS=1 runs them one at a time).
catkin_make -j2 -DCATKIN_ENABLE_TESTING=ON tests 2>&1 | grep -E 'error|warning' | head -n 50
if [ "$quick" = 1 ]; then
  echo "== gtests, nosetests and fuzz targets (no simulation, no master)"
  python3 "$root/scripts/test_pool.py" --quick
else
  echo "== unit tests and rostests (scripts/test_pool.py)"
  python3 "$root/scripts/test_pool.py"
  echo "== the recipes of docs/adding.md: a board and a device added as a user does (scripts/check_recipe.sh)"
  bash "$root/scripts/check_recipe.sh" build/test_results/recipe/recipe_check.xml 2>&1 | grep '^recipe:'
fi
echo "== results"
catkin_test_results --verbose build/test_results > build/test_summary.txt 2>&1; results_rc=$?
grep -vE '^\s*$' build/test_summary.txt | tail -n 60

# One closing line: count test cases from the JUnit files.
python3 - "$lint_problems" <<'PY'
import glob, sys, xml.etree.ElementTree as ET
total = failed = skipped = 0
failures = []  # (file, case, first lines of the message): printed last, where a cut log still shows them
for f in sorted(glob.glob('build/test_results/**/*.xml', recursive=True)):
    try:
        root = ET.parse(f).getroot()
    except ET.ParseError as e:
        failed += 1
        failures.append((f, '(unreadable result file)', str(e)))
        continue
    suites = [root] if root.tag == 'testsuite' else root.iter('testsuite')
    for s in suites:
        if not list(s.iter('testcase')) and int(s.get('errors', 0) or 0) + int(s.get('failures', 0) or 0):
            # rostest writes an empty suite with errors="1" when its test node never reported
            # (did not start, crashed, or ran past its time-limit).
            total += 1
            failed += 1
            failures.append((f, '(no test case ran)', 'the test node never reported: crash, start failure or time-limit'))
        for case in s.iter('testcase'):
            total += 1
            bad = case.find('failure')
            if bad is None:
                bad = case.find('error')
            if bad is not None:
                failed += 1
                text = (bad.get('message') or '') + '\n' + (bad.text or '')
                lines = [l for l in text.splitlines() if l.strip()]
                failures.append((f, case.get('name'), '\n      '.join(lines[-6:])))
            elif case.find('skipped') is not None:
                skipped += 1
for f, case, why in failures:
    print('FAILED %s :: %s\n      %s' % (f.replace('build/test_results/', ''), case, why[-1500:]))
lint = int(sys.argv[1])
if lint:
    print('catkin_lint: %d problem(s)' % lint)
print('%d passed, %d failed, %d skipped' % (total - failed - skipped, failed + (1 if lint else 0), skipped))
PY
if [ "$results_rc" != 0 ] || [ "$lint_problems" != 0 ] || ! ls build/test_results/*/*.xml >/dev/null 2>&1; then
  echo "TESTS FAILED"
  exit 1
fi
echo "ALL TESTS PASSED"
