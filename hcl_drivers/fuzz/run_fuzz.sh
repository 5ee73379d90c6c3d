#!/usr/bin/env bash
# Runs one libFuzzer target for a few seconds from a fixed seed and writes a JUnit result for
# catkin_test_results (a crash is a failed test case; the script itself exits 0).
#   run_fuzz.sh <fuzzer binary> <junit xml> <seconds>
# Inputs in fuzz/seeds/<fuzzer name>/, when there are any, start its corpus.
set -u
bin=$1; xml=$2; secs=${3:-5}
name=$(basename "$bin")
mkdir -p "$(dirname "$xml")"
work=$(mktemp -d)
seeds="$(dirname "$0")/seeds/$name"
[ -d "$seeds" ] && cp "$seeds"/* "$work/" 2>/dev/null
start=$(date +%s%N)
"$bin" -seed=1 -max_total_time="$secs" -max_len=256 -timeout=5 -rss_limit_mb=1024 -print_final_stats=1 \
  -artifact_prefix="$work/" "$work" > "$work/log.txt" 2>&1
rc=$?
ms=$(( ($(date +%s%N) - start) / 1000000 ))
dur="$((ms / 1000)).$(printf %03d $((ms % 1000)))"
runs=$(grep -oE 'stat::number_of_executed_units: *[0-9]+' "$work/log.txt" | grep -oE '[0-9]+$' || echo 0)
echo "$name: rc=$rc, $runs inputs in ${secs}s"
{
  echo '<?xml version="1.0" encoding="UTF-8"?>'
  if [ "$rc" = 0 ]; then
    echo "<testsuite name=\"fuzz\" tests=\"1\" failures=\"0\" errors=\"0\" time=\"$dur\">"
    echo "  <testcase classname=\"fuzz\" name=\"$name\" time=\"$dur\"><system-out>$runs inputs, no crash</system-out></testcase>"
  else
    echo "<testsuite name=\"fuzz\" tests=\"1\" failures=\"1\" errors=\"0\" time=\"$dur\">"
    echo "  <testcase classname=\"fuzz\" name=\"$name\" time=\"$dur\"><failure message=\"libFuzzer found a crash (rc=$rc)\"><![CDATA["
    tail -n 60 "$work/log.txt" | sed 's/]]>/]] >/g'
    echo "]]></failure></testcase>"
  fi
  echo "</testsuite>"
} > "$xml"
[ "$rc" = 0 ] && rm -rf "$work"
exit 0
