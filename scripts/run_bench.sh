#!/usr/bin/env bash
# Runs every benchmark script in scripts/bench/ (workspace sourced by `make bench`) and
# prints their figures. A failing benchmark is reported but does not hide the others.
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
failed=0
for b in scripts/bench/*.sh; do
  [ -e "$b" ] || continue
  echo "==== $(basename "$b" .sh)"
  if ! bash "$b"; then
    echo "benchmark $b FAILED"
    failed=1
  fi
done
exit $failed
