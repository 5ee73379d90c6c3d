#!/usr/bin/env bash
# run_fuzz.sh FUZZER XUNIT_XML SECONDS: runs a libFuzzer target briefly from a fixed seed and
# writes a JUnit result for catkin_test_results.
set -u
fuzzer=$1; xml=$2; seconds=$3
name=$(basename "$fuzzer")
corpus=$(mktemp -d /tmp/${name}_corpus.XXXXXX)
printf '$B1,4711*5C\r\n$B0,0*6E\r\n' > "$corpus/seed1"
printf 'junk$B2,12*\n$B1,47' > "$corpus/seed2"
log=$(mktemp /tmp/${name}_log.XXXXXX)
"$fuzzer" -seed=1 -max_total_time="$seconds" -timeout=5 -rss_limit_mb=1024 -artifact_prefix="$corpus/" "$corpus" >"$log" 2>&1
rc=$?
runs=$(grep -oE 'Done [0-9]+ runs' "$log" | grep -oE '[0-9]+' | tail -n1)
mkdir -p "$(dirname "$xml")"
if [ $rc = 0 ]; then
  echo "$name: ${runs:-?} runs in ${seconds}s, no crash"
  cat > "$xml" <<XML
<?xml version="1.0" encoding="UTF-8"?>
<testsuite name="$name" tests="1" failures="0" errors="0"><testcase classname="fuzz" name="$name"/></testsuite>
XML
else
  tail -n 30 "$log"
  msg=$(tail -n 30 "$log" | sed 's/[<>&"]/_/g')
  cat > "$xml" <<XML
<?xml version="1.0" encoding="UTF-8"?>
<testsuite name="$name" tests="1" failures="1" errors="0"><testcase classname="fuzz" name="$name"><failure message="libFuzzer found a failing input">$msg</failure></testcase></testsuite>
XML
fi
rm -rf "$corpus" "$log"
exit $rc
