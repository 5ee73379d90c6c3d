# The project's commands. Everything runs as root on Debian bookworm, with Debian's
# python3 first on PATH (the machine's own python3 has no ROS modules).
#   make new-robot NAME=my_robot [FROM=skeleton|eurobot2009|logion]  a new robot's files from a template
#   make check-config [ROBOT=eurobot2009] [OVERLAY=a.yaml] [STRATEGY=name] [SIDE=zone]  every config reader, no master, in seconds
#   make run [ROBOT=eurobot2009] [STRATEGY=name] [SEED=1] [OVERLAY=params.yaml] [SIDE=zone]  install, build, run
#                               one simulated match headless (also logion; skeleton runs until
#                               Ctrl-C), print the score (ours, opponent), bag and report paths: a
#                               folder of its own, report/ROBOT/<UTC time>_seed<k>/, and
#                               report/ROBOT/latest to the last complete one
#   make matches [ROBOT=eurobot2009] [N=20] [SEED=1] [FACTOR=0] [CLUSTER=tcp://HOST:8786]
#                [WORKERS=W] [FETCH_BAGS=1] [OVERLAY=params.yaml] [SIDE=zone]  install, build, run N seeded
#                               matches headless on a Dask cluster (CLUSTER's scheduler, else a
#                               local one of WORKERS processes, default one per 2 cores; opponent:
#                               random walk, route, blocker, player in turn), a row per match,
#                               report/ROBOT/matches_<UTC time>/ (reports, summary PNG; bags stay on
#                               remote workers unless FETCH_BAGS=1), win rates; exits non-zero when
#                               a match broke an invariant
#   make play [ROBOTS=eurobot2009,logion] [N=20] [SEED=1] [FACTOR=0]  the scoreboard: make matches
#                               for each robot, then each figure (mean score and its 95 % interval,
#                               zero scores, win rate against `player`, stalls and idle per match,
#                               violations) against config/scoreboard.yaml; closing line
#                               `scoreboard: robots R matches M targets_met T of K`
#   make tune [ROBOT=eurobot2009] [TRIALS=50] [SEEDS=5] [HOLDOUT=H] [HOLDOUT_SEED=K] [CLUSTER=...]
#             [WORKERS=W] [STORAGE=URL]  an Optuna
#                               study over config/tune/ROBOT.yaml, SEEDS matches per trial, then
#                               the best overlay against the shipped config on held-out seeds;
#                               report/tune/; closing line `trials T best_score B baseline_score S
#                               improvement D ci95 [L, H]`
#   make scheduler | make worker CLUSTER=tcp://HOST:8786 [WORKERS=W]  a Dask scheduler, or
#                               workers for it, with this workspace's environment
#   make chaos [ROBOT=eurobot2009] [N=10] [SEED=1] [FACTOR=0]  install, build, run N seeded
#                               matches with faults injected mid-match (every fault class: buses,
#                               world, processes), check the invariants, a row per match,
#                               report/ROBOT/chaos_<UTC time>/; closing line `matches N faults F violations V`,
#                               exits non-zero on any violation
#   make soak [ROBOT=eurobot2009] [N=10] [SEED=1] [FACTOR=0]  make matches and make chaos, N each,
#                               one summary (violations by class, false alarms, worst recovery
#                               per fault class, scores with and without faults), report/ROBOT/
#                               soak_<UTC time>/; closing line `soak ROBOT matches M chaos C violations V`
#   make doctor [ROBOT=eurobot2009] [SIM=1] [JSON=1]  build, then check every board of the robot on
#                               its real channel without starting the product (rosrun hcl_drivers
#                               doctor ROBOT): one table, exit 1 on any FAIL; SIM=1 starts the
#                               simulator's emulators alone and checks them
#   make test                   install, build, run every unit test and rostest
#   make check                  build, then the quick tier: catkin_lint, gtests, nosetests and
#                               fuzz targets, no simulation (a few minutes after the build)
#   make bench                  install, build, print the benchmarks' figures
#   make docs                   build, then write each package's PARAMETERS.md from the parameter
#                               readers themselves (scripts/parameter_tables.py)
#   make report [BAG=x.bag]     match report PNG of a recorded bag
#   make calibrate BAG=x.bag [ROBOT=..] [OUT=config]  fit the robot's geometry and the simulator's
#                               model of it (motors, slip, rangers, beacons) to a recorded match:
#                               OUT/ROBOT.calibrated.yaml, OUT/ROBOT.calibrated.sim.yaml (overlays),
#                               a report beside the bag; closing line `calibrate ROBOT: P parameters,
#                               fit_rmse_wheel_speed S m/s, odometry_drift_after D mm/m (before B mm/m)`
#   make replay BAG=x.bag [ROBOT=..] [THROUGH=localization|hal] [RATE=1] [SIM=1]  replay a recorded
#                               match; exit 3 when fewer than 95 % of its estimates come again
#   make install-robot [ROBOT=eurobot2009] [START=1] [ROOT=DIR] [DRY_RUN=1]  on the robot's own
#                               computer (built workspace): CAN interfaces up at their bitrate at
#                               boot, udev names for its USB devices, the nftables firewall of its
#                               ROS ports (only the robot and computer/network/allow get in),
#                               robot-ROBOT.service (roslaunch sim:=false at boot on the robot's
#                               address, ROS_IP; started now only with START=1);
#                               ROOT= installs into a staging root and calls nothing on this
#                               machine, DRY_RUN=1 only lists (docs/real-robot.md "The robot's computer")
#   make uninstall-robot [ROBOT=eurobot2009] [ROOT=DIR] [DRY_RUN=1]  stops, disables and removes
#                               what install-robot installed (its manifest,
#                               /var/lib/robot/ROBOT/installed.txt)
#   make allow-laptop ROBOT=eurobot2009 ADDR=192.168.1.20 | make deny-laptop ROBOT=... ADDR=...
#                               let a laptop (rviz) into the running firewall, or out again; not
#                               kept across a reboot or reinstall (for good: computer/network/allow)
#   make firewall-status [ROBOT=eurobot2009]  what the firewall allows, how much it dropped
#   make deps | build | lint | clean

SHELL := /bin/bash
export PATH := /usr/bin:/bin:/usr/sbin:/sbin:$(PATH)
export PYTHONNOUSERSITE := 1
export ROS_PYTHON_VERSION := 3
# Only C++ and Python messages are used: skip the Lisp, EusLisp and JavaScript generators.
export ROS_LANG_DISABLE := genlisp:geneus:gennodejs

ROBOT ?= eurobot2009
STRATEGY ?=
SEED ?= 1
OVERLAY ?=
# SIDE=green: play from that start zone (robot_core.start_zone.side_overlay: the simulated robot,
# its initial_pose, its side switch and the opponent's start follow it)
SIDE ?=
# OVERLAY="a.yaml b.yaml": several overlays, each over the one before (the runners take them comma-separated)
comma := ,
empty :=
space := $(empty) $(empty)
OVERLAY_ARG = $(subst $(space),$(comma),$(strip $(abspath $(OVERLAY))))
N ?=
FACTOR ?= 0
CLUSTER ?=
WORKERS ?=
TRIALS ?= 50
SEEDS ?= 5
STORAGE ?=
DRY_RUN ?=
START ?=
# ROOT is the repository. `make install-robot ROOT=DIR` names a staging root instead: taken as
# STAGE here, then ROOT is the repository again (override: a command-line ROOT would replace it).
STAGE := $(if $(filter command line,$(origin ROOT)),$(ROOT))
override ROOT := $(abspath $(dir $(lastword $(MAKEFILE_LIST))))
JOBS ?= 2
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
SETUP := source $(ROOT)/devel/setup.bash

# The one explicit list of Debian packages (rosdep has no index here).
DEPS := build-essential cmake catkin python3-catkin-pkg catkin-lint \
  ros-base-dev ros-core-dev libnodelet-dev pluginlib-dev libactionlib-dev python3-actionlib \
  libdiagnostic-updater-dev python3-diagnostic-updater libdiagnostic-msgs-dev python3-diagnostic-msgs \
  libdiagnostic-aggregator-dev libdiagnostic-aggregator-tools rosdiagnostic \
  libnav-msgs-dev python3-nav-msgs libsensor-msgs-dev python3-sensor-msgs \
  libgeometry-msgs-dev python3-geometry-msgs libvisualization-msgs-dev python3-visualization-msgs \
  libstd-srvs-dev python3-std-srvs libtf2-ros-dev python3-tf2-ros libtf2-geometry-msgs-dev python3-tf2-geometry-msgs \
  librosbag-dev python3-rosbag librostest-dev python3-rostest rosbash python3-roslaunch python3-rosnode \
  python3-rostopic python3-rosservice python3-rosparam rosout \
  ros-robot-state-publisher liburdf-dev libcv-bridge-dev python3-cv-bridge libimage-transport-dev libopencv-dev \
  libmrpt-dev libmrpt-ros1bridge-dev libeigen3-dev libyaml-cpp-dev \
  libgtest-dev libgmock-dev googletest python3-nose python3-numpy \
  can-utils iproute2 socat
# the robot's computer: the firewall of its ROS ports (make install-robot, /usr/sbin/nft)
DEPS += nftables
# product: rviz and its headless test (Xvfb + screenshot), the match report's plots
DEPS += rviz xvfb xauth imagemagick python3-matplotlib python3-pil openssh-server
# the rviz match panel plugin (match_panel): rviz headers and Qt 5
DEPS += librviz-dev qtbase5-dev
# ROS users' usual tools and interfaces: tf_echo / view_frames, move_base's action messages
DEPS += tf-tools python3-tf libmove-base-msgs-dev python3-move-base-msgs
# matches at scale: Dask distributed, Optuna (its parameter importances need scikit-learn)
DEPS += python3-distributed python3-optuna python3-sklearn
# libFuzzer (clang) for the beacon parser fuzz test
DEPS += clang libclang-rt-14-dev
# the benches on a loaded computer (scripts/bench/loaded_match.sh, latency.sh --stress)
DEPS += stress-ng
# The real SocketCAN test needs a VM on a kernel without AF_CAN: `make test` installs
# its kernel, qemu and virtme-ng in the background while it builds (scripts/can_vm_prepare.sh,
# nothing where vcan0 works or with CAN_VM_TEST=0); `make deps` does not.

.PHONY: deps build run test bench lint clean report

deps:
	@if dpkg -s $(DEPS) >/dev/null 2>&1; then echo "deps: all Debian packages present"; else \
	  $(SUDO) apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends $(DEPS) >/dev/null && \
	  echo "deps: installed"; fi

# Every reader the nodes run at start, over the config, its sim overlay and OVERLAY, with no ROS
# master: errors in seconds, one line each (robot_description/scripts/check_config). The runners
# below run it first and start nothing on an error; every robot's launch file runs it too.
CHECK_CONFIG = $(SETUP) && $(ROOT)/robot_description/scripts/check_config $(ROBOT) \
  $(if $(OVERLAY),--overlay $(OVERLAY_ARG)) $(if $(STRATEGY),--strategy $(STRATEGY)) $(if $(SIDE),--side $(SIDE))
.PHONY: check-config
check-config:
	@test -x $(ROOT)/devel/lib/hal_nodes/check_hal_config || $(MAKE) build
	@$(CHECK_CONFIG)

build: deps
	cd $(ROOT) && catkin_make -j$(JOBS) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPYTHON_EXECUTABLE=/usr/bin/python3 \
	  -DCATKIN_ENABLE_TESTING=ON

run: build
	@$(CHECK_CONFIG)
	$(SETUP) && python3 $(ROOT)/scripts/run_match.py $(ROBOT) --seed $(SEED) $(if $(STRATEGY),--strategy $(STRATEGY)) \
	  $(if $(OVERLAY),--overlay $(OVERLAY_ARG)) $(if $(SIDE),--side $(SIDE))

# N seeded matches (seeds SEED, SEED+1, ...) at real_time_factor FACTOR (0: as fast as the machine goes).
.PHONY: matches
matches: build
	@$(CHECK_CONFIG)
	$(SETUP) && python3 $(ROOT)/scripts/run_matches.py $(ROBOT) --n $(or $(N),20) --seed $(SEED) --factor $(FACTOR) \
	  $(if $(STRATEGY),--strategy $(STRATEGY)) $(if $(CLUSTER),--cluster $(CLUSTER)) \
	  $(if $(WORKERS),--workers $(WORKERS)) $(if $(FETCH_BAGS),--fetch-bags) $(if $(OVERLAY),--overlay $(OVERLAY_ARG)) \
	  $(if $(SIDE),--side $(SIDE))

# The scoreboard: N matches per robot against config/scoreboard.yaml's targets (scripts/scoreboard.py).
ROBOTS ?= eurobot2009,logion
.PHONY: play
play: build
	@for r in $(subst $(comma),$(space),$(ROBOTS)); do $(SETUP) && $(ROOT)/robot_description/scripts/check_config $$r || exit 1; done
	$(SETUP) && python3 $(ROOT)/scripts/scoreboard.py --robots $(ROBOTS) --n $(or $(N),20) --seed $(SEED) --factor $(FACTOR)

# An Optuna study of config/tune/ROBOT.yaml's parameters (scripts/tune.py).
.PHONY: tune
tune: build
	@$(CHECK_CONFIG)
	$(SETUP) && python3 $(ROOT)/scripts/tune.py $(ROBOT) --trials $(TRIALS) --seeds $(SEEDS) --seed $(SEED) \
	  --factor $(FACTOR) $(if $(CLUSTER),--cluster $(CLUSTER)) $(if $(WORKERS),--workers $(WORKERS)) \
	  $(if $(STORAGE),--storage $(STORAGE)) $(if $(HOLDOUT),--holdout $(HOLDOUT)) \
	  $(if $(HOLDOUT_SEED),--holdout-seed $(HOLDOUT_SEED))

# A Dask scheduler (port 8786) and workers for it, on any machine with this workspace built: the
# workers need ROS's environment and scripts/ on their path; one single-threaded worker process
# per 2 cores (a match at full speed keeps two busy). A worker that dies mid-match costs that match one retry.
.PHONY: scheduler worker
scheduler: deps
	DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES=1 dask scheduler --port 8786 --dashboard-address :8787
worker: build
	@test -n "$(CLUSTER)" || { echo "make worker: CLUSTER=tcp://HOST:8786 (the scheduler's address)"; exit 2; }
	$(SETUP) && dask worker $(CLUSTER) --nthreads 1 \
	  --nworkers $(or $(WORKERS),$$(( $$(nproc) > 3 ? $$(nproc) / 2 : 1 ))) --local-directory /tmp/robot_matches

# N seeded matches with a fault schedule each (scripts/run_chaos.py, robot_tools.chaos.faults).
.PHONY: chaos
chaos: build
	@$(CHECK_CONFIG)
	$(SETUP) && python3 $(ROOT)/scripts/run_chaos.py $(ROBOT) --n $(or $(N),10) --seed $(SEED) \
	  --factor $(FACTOR)

# make matches then make chaos, N each, one summary (scripts/soak.py).
.PHONY: soak
soak: build
	@$(CHECK_CONFIG)
	$(SETUP) && python3 $(ROOT)/scripts/soak.py $(ROBOT) --n $(or $(N),10) --seed $(SEED) --factor $(FACTOR)

# The hardware doctor (hcl_drivers/scripts/doctor).
.PHONY: doctor
doctor: build
	$(SETUP) && rosrun hcl_drivers doctor $(ROBOT) $(if $(filter 1,$(SIM)),--sim --start-sim) $(if $(filter 1,$(JSON)),--json)

test: deps
	@bash $(ROOT)/scripts/can_vm_prepare.sh --background
	$(MAKE) build
	$(SETUP) && cd $(ROOT) && bash $(ROOT)/scripts/run_tests.sh

# The quick tier of `make test`: what needs no simulation and no ROS master.
.PHONY: check
check: build
	$(SETUP) && cd $(ROOT) && bash $(ROOT)/scripts/run_tests.sh --quick

bench: build
	$(SETUP) && cd $(ROOT) && bash $(ROOT)/scripts/run_bench.sh

# A recorded match replayed (launch/replay.launch), its faithfulness as the exit code (scripts/replay.py).
THROUGH ?= localization
RATE ?= 1
.PHONY: replay
replay: build
	@test -n "$(BAG)" || { echo "make replay: BAG=path.bag [ROBOT=eurobot2009] [THROUGH=localization|hal] [RATE=1] [SIM=1]"; exit 2; }
	$(SETUP) && python3 $(ROOT)/scripts/replay.py $(abspath $(BAG)) --robot $(ROBOT) --through $(THROUGH) --rate $(RATE) \
	  $(if $(filter 1,$(SIM)),--sim)

# A new robot's files from a template (scripts/new_robot.py): config, sim overlay, launch, URDF, rviz.
.PHONY: new-robot
new-robot:
	@test -n "$(NAME)" || { echo "make new-robot NAME=my_robot [FROM=skeleton|eurobot2009|logion]"; exit 2; }
	@test -x $(ROOT)/devel/lib/hal_nodes/check_hal_config || $(MAKE) build
	$(SETUP) && python3 $(ROOT)/scripts/new_robot.py $(NAME) --from $(or $(FROM),skeleton)

# The robot and the simulator's model of it fitted to one recorded match (scripts/calibrate.py).
.PHONY: calibrate
calibrate: build
	@test -n "$(BAG)" || { echo "make calibrate: BAG=path.bag [ROBOT=eurobot2009] [OUT=config]"; exit 2; }
	$(SETUP) && python3 $(ROOT)/scripts/calibrate.py $(ROBOT) $(abspath $(BAG)) $(if $(OUT),--out $(abspath $(OUT)))

# Match report of a recorded bag (record:=true): PNG + text next to the bag.
#   make report [BAG=path.bag]   (default: the newest bag in ~/.ros)
report: deps
	python3 $(ROOT)/scripts/match_report.py $(BAG)

# The robot's computer (scripts/robot_install.py): needs the workspace built, does not build it.
INSTALL_ROBOT_ARGS = $(ROBOT) $(if $(STAGE),--root $(STAGE)) $(if $(filter-out 0,$(DRY_RUN)),--dry-run)
.PHONY: install-robot uninstall-robot allow-laptop deny-laptop firewall-status
install-robot:
	@test -f $(ROOT)/devel/setup.bash || { echo "make install-robot: $(ROOT)/devel/setup.bash missing: build the workspace first (make build)"; exit 2; }
	python3 $(ROOT)/scripts/robot_install.py install $(INSTALL_ROBOT_ARGS) $(if $(filter-out 0,$(START)),--start)
uninstall-robot:
	python3 $(ROOT)/scripts/robot_install.py uninstall $(INSTALL_ROBOT_ARGS)
# The running firewall's allow-list, for one match (docs/real-robot.md "Nobody outside the robot drives it").
ADDR ?=
allow-laptop deny-laptop:
	@test -n "$(ADDR)" || { echo "make $@: ADDR=<the laptop's IPv4 address> (ROBOT=$(ROBOT))"; exit 2; }
	python3 $(ROOT)/scripts/robot_install.py $(patsubst %-laptop,%,$@) $(ROBOT) $(ADDR)
firewall-status:
	python3 $(ROOT)/scripts/robot_install.py status $(ROBOT)

# Each package's parameter tables, from the readers' own declarations (test_parameter_tables
# fails when the committed ones differ).
.PHONY: docs
docs: build
	$(SETUP) && python3 $(ROOT)/scripts/parameter_tables.py

lint: build  # the nodelet plugin XMLs it checks are generated by the build
	catkin_lint -W1 $(ROOT)/src

clean:
	rm -rf $(ROOT)/build $(ROOT)/devel
