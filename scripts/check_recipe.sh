#!/usr/bin/env bash
# The recipes "Adding a board" and "Adding a device" (docs/adding.md), done as a new user does them, so
# they cannot rot: copies the example board (driver + its state message), its emulator and the
# example device under new names, drops in a test launch, builds with no list or XML edited,
# launches the skeleton with one config overlay for the new pieces, and checks that the new
# device publishes from the new board and raises its /diagnostics level. The copies are removed
# and the libraries rebuilt on exit, whatever happens.
#   scripts/check_recipe.sh [JUNIT.xml]       (make test runs it after the rostests)
set -uo pipefail
export ROS_LANG_DISABLE=${ROS_LANG_DISABLE:-genlisp:geneus:gennodejs}  # as the Makefile builds
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
junit=${1:-}
port=27160           # the new board's emulated UDP endpoint (the skeleton's own board is on 27100)
master_port=11390    # a master of its own: never the one of a test or of the user's session

board=hcl_drivers/src/boards/example/recipe_check_board.cpp
message=hcl_drivers/msg/RecipeCheckBoardState.msg
emulator=robot_sim/src/firmware/example/recipe_check_board.cpp
device=hal_nodes/src/devices/recipe_check/recipe_check_device.cpp
test_launch=test/launch/recipe_check.test
created=("$board" "$message" "$emulator" "$device" "$test_launch")
work=$(mktemp -d /tmp/recipe_check.XXXXXX)
git status --porcelain > "$work/status_before.txt"
targets="hcl_boards hcl_boards_plugin_xml hal_devices hal_devices_plugin_xml robot_sim_firmware"

cases=()   # "name|failure message or empty"
result() { cases+=("$1|$2"); if [ -z "$2" ]; then echo "recipe: ok   $1"; else echo "recipe: FAIL $1: $2"; fi; }

cleanup() {
  [ -n "${launch_pid:-}" ] && kill -INT "$launch_pid" 2>/dev/null && wait "$launch_pid" 2>/dev/null
  rm -f "${created[@]}"; rmdir "$(dirname "$device")" 2>/dev/null
  echo "recipe: copies removed, rebuilding the libraries without them"
  (cd build && make -j2 $targets >"$work/rebuild.log" 2>&1) || { echo "recipe: rebuild failed, see $work/rebuild.log"; }
  if [ -n "$junit" ]; then
    mkdir -p "$(dirname "$junit")"
    python3 - "$junit" "${cases[@]}" <<'PY'
import sys
from xml.sax.saxutils import escape, quoteattr
out, cases = sys.argv[1], [c.split('|', 1) for c in sys.argv[2:]]
failed = sum(1 for _, why in cases if why)
with open(out, 'w') as f:
    f.write('<?xml version="1.0" encoding="utf-8"?>\n<testsuite name="recipe_check" tests="%d" failures="%d" errors="0">\n'
            % (len(cases), failed))
    for name, why in cases:
        f.write('  <testcase classname="recipe_check" name=%s>' % quoteattr(name))
        f.write('<failure message=%s>%s</failure>' % (quoteattr(why), escape(why)) if why else '')
        f.write('</testcase>\n')
    f.write('</testsuite>\n')
PY
  fi
  for c in "${cases[@]}"; do [ -n "${c#*|}" ] && exit 1; done
  [ ${#cases[@]} -gt 0 ] || exit 1
  exit 0
}
trap cleanup EXIT

# 1. The files, and nothing else: a board (driver, state message, emulator), a device, a test.
sed 's/ExampleBoard/RecipeCheckBoard/g' hcl_drivers/src/boards/example/example_board.cpp > "$board"
cp hcl_drivers/msg/ExampleBoardState.msg "$message"
sed 's/ExampleBoard/RecipeCheckBoard/g' robot_sim/src/firmware/example/example_board.cpp > "$emulator"
mkdir -p "$(dirname "$device")"
sed -e 's/ExampleDevice/RecipeCheckDevice/g' -e 's/ExampleBoardState/RecipeCheckBoardState/g' \
  hal_nodes/src/devices/example/example_device.cpp > "$device"
sed 's/skeleton_end_to_end/recipe_check/' test/launch/skeleton.test > "$test_launch"

# 2. Build, as a user does after adding files: nothing registered by hand.
echo "recipe: building with the new files (log: $work/build.log)"
if (cd build && make -j2 $targets >"$work/build.log" 2>&1 && make help >"$work/targets.txt"); then
  result build ""
else
  result build "the build failed with the recipe's files: $(grep -m3 -E 'error|Error' "$work/build.log" | tr '\n' ' ')"
  exit 0
fi
# nothing else changed: the only new entries of `git status` are the files written above
git status --porcelain | grep -vF -e "${board}" -e "${message}" -e "${emulator}" -e "recipe_check/" -e "${test_launch}" \
  > "$work/status_after.txt"
edited=$(diff "$work/status_before.txt" "$work/status_after.txt" | grep '^>' | tr '\n' ' ')
[ -z "$edited" ] && result nothing_else_edited "" || result nothing_else_edited "the build changed: $edited"
grep -q 'hcl_drivers/RecipeCheckBoard"' hcl_drivers/nodelet_plugins.xml && result board_exported "" ||
  result board_exported "hcl_drivers/RecipeCheckBoard is not in the generated nodelet_plugins.xml"
grep -q 'hal_nodes/RecipeCheckDevice"' hal_nodes/nodelet_plugins.xml && result device_exported "" ||
  result device_exported "hal_nodes/RecipeCheckDevice is not in the generated nodelet_plugins.xml"
# every export line is one well-formed <class> (pluginlib silently drops what follows a bad entry)
xml_check=$(python3 - <<'PY'
import glob, re, xml.dom.minidom
for pkg, macro, folder in (('hcl_drivers', 'HCL_EXPORT_BOARD', 'src/boards'), ('hal_nodes', 'HAL_EXPORT_DEVICE', 'src/devices')):
    exports = sum(len(re.findall(r'^%s\(' % macro, open(f).read(), re.M)) for f in glob.glob('%s/%s/*/*.cpp' % (pkg, folder)))
    try:
        classes = len(xml.dom.minidom.parse('%s/nodelet_plugins.xml' % pkg).getElementsByTagName('class'))
    except Exception as e:
        print('%s/nodelet_plugins.xml: %s' % (pkg, e)); continue
    if classes != exports:
        print('%s/nodelet_plugins.xml has %d classes for %d %s lines' % (pkg, classes, exports, macro))
PY
)
result plugin_xml_complete "$xml_check"
grep -q 'recipe_check' "$work/targets.txt" && result test_picked_up "" ||
  result test_picked_up "no build target runs test/launch/recipe_check.test"

# 3. Run it: the skeleton plus one overlay with the new board, its emulator and the new device.
cat > "$work/overlay.yaml" <<YAML
hcl:
  recipe_board: {type: RecipeCheckBoard, rate: 50, endpoint: "udp://127.0.0.1:$port", command_timeout: 0.5}
hal:
  recipe_device: {type: RecipeCheckDevice, rate: 20, board_state: /hcl/recipe_board/state,
                  board_lamp: /hcl/recipe_board/lamp_pwm, max_input_age: 0.5, warn_above: 0.0}
sim:
  firmware:
    recipe_board: {type: RecipeCheckBoard, endpoint: "udp://127.0.0.1:$port", dial_period: 8.0}
YAML
export ROS_MASTER_URI=http://localhost:$master_port
roslaunch -p $master_port launch/skeleton.launch overlay:="$work/overlay.yaml" sim_dir:="$work/sim" \
  >"$work/launch.log" 2>&1 &
launch_pid=$!
printf 'reading|the check did not run\nwarn|the check did not run\n' > "$work/check.txt"
python3 - "$work/check.txt" <<'PY'
import sys, time
import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from hal_nodes.msg import ExampleReading
deadline = time.monotonic() + 60
while True:
    try:
        rospy.get_master().getPid()
        break
    except Exception:
        if time.monotonic() > deadline:
            open(sys.argv[1], 'w').write('reading|no ROS master\nwarn|no ROS master\n')
            sys.exit(0)
        time.sleep(0.2)
rospy.init_node('recipe_check', anonymous=True)
seen = {'reading': None, 'warn': None}
def on_reading(m):
    seen['reading'] = m
def on_diag(m):
    for s in m.status:
        if 'hal/recipe_device' in s.name:
            seen['warn'] = s
rospy.Subscriber('/hal/recipe_device/reading', ExampleReading, on_reading)
rospy.Subscriber('/diagnostics', DiagnosticArray, on_diag)
deadline = time.monotonic() + 60
def warned():
    w = seen['warn']
    return w is not None and w.level == DiagnosticStatus.WARN and 'dial at' in w.message
while time.monotonic() < deadline and not (seen['reading'] and warned()):
    time.sleep(0.1)
lines = ['reading|' + ('' if seen['reading'] else 'nothing on /hal/recipe_device/reading in 60 s')]
w = seen['warn']
lines.append('warn|' + ('' if warned() else
                        'the device did not raise its level with setCondition: %s' % str(w and (w.level, w.message))))
open(sys.argv[1], 'w').write('\n'.join(lines) + '\n')
PY
while IFS='|' read -r name why; do
  result "device_${name}" "$why"
done < "$work/check.txt"
kill -INT "$launch_pid" 2>/dev/null; wait "$launch_pid" 2>/dev/null; launch_pid=
echo "recipe: touch points: board ${board##*/}, ${message##*/} (its state), emulator ${emulator##*/}, device ${device##*/}, test ${test_launch##*/}, one config overlay; 0 lists edited"
