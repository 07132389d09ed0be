# The two commands of this workspace:
#   make demo   build everything, then run the main job
#   make test   build everything, lint it (tools/lint.sh: ruff and mypy), then run every package's
#               tests (colcon test, four lanes at once: tools/test_lanes.sh)
# Both set themselves up from nothing: virtual environment with pinned wheels, CMake fix, colcon build.

SHELL := /bin/bash
.DEFAULT_GOAL := build

VENV_STAMP  := .venv/.wurde-installed
BUILD_STAMP := install/.wurde-built
IN_ENV      := tools/in_env.sh
# Everything colcon would build from; a change to any of these rebuilds, nothing else does.
SOURCES     := $(shell find src -type f -not -path '*/__pycache__/*' -not -name '*.pyc' 2>/dev/null) colcon.meta
COLCON_BUILD_ARGS ?= --event-handlers console_cohesion+ --cmake-args -DBUILD_TESTING=ON
COLCON_TEST_ARGS  ?= --event-handlers console_cohesion+ --return-code-on-test-failure
DEMO_DOMAIN_ID    ?= 57

.PHONY: build test demo clean distclean system

build: $(BUILD_STAMP)

# Debian packages the tests need beyond the venv (xvfb, libxtst6, chromium: the Eye's window and
# page are tested on real screens). No stamp: the check is a dpkg-query (a few ms) and installs only
# what is missing, so a package removed since is put back. The demo and `make build` need none.
system:
	tools/setup_system.sh

$(VENV_STAMP): $(wildcard requirements*.txt) tools/setup_venv.sh tools/fix_ros_wheel_cmake.py
	tools/setup_venv.sh

# The stamp takes the time the build started, so a file edited during a build rebuilds next time.
$(BUILD_STAMP): $(VENV_STAMP) $(SOURCES)
	@mkdir -p install && touch install/.wurde-build-started
	$(IN_ENV) colcon build $(COLCON_BUILD_ARGS)
	@mv install/.wurde-build-started $@

test: build system
	@rc=0; \
	tools/lint.sh || rc=$$?; \
	tools/test_lanes.sh $(COLCON_TEST_ARGS) || rc=$$((rc ? rc : $$?)); \
	$(IN_ENV) colcon test-result --verbose || rc=$$((rc ? rc : $$?)); \
	$(IN_ENV) python tools/test_summary.py build || rc=$$((rc ? rc : $$?)); \
	exit $$rc

demo: build
	ROS_DOMAIN_ID=$(DEMO_DOMAIN_ID) $(IN_ENV) python tools/demo.py $(DEMO_ARGS)

clean:
	rm -rf build install log

distclean: clean
	rm -rf .venv .venv-docs

# The manual as a static site (issue 40): mkdocs with mkdocs-material, pinned in
# requirements-docs.txt and installed into .venv-docs (not the workspace's venv), built with warnings
# as errors into build/site. Not part of `make test`; the tests check the pages' links and examples.
DOCS_VENV := .venv-docs
.PHONY: docs
$(DOCS_VENV)/.installed: requirements-docs.txt
	python3 -m venv $(DOCS_VENV)
	$(DOCS_VENV)/bin/python -m pip install --quiet --disable-pip-version-check -r requirements-docs.txt
	touch $@

docs: $(DOCS_VENV)/.installed
	NO_MKDOCS_2_WARNING=1 $(DOCS_VENV)/bin/mkdocs build --strict

# Benchmarks (not tests): compare wurde_core with raw rclpy in the same run.
.PHONY: bench
bench: build
	$(IN_ENV) python bench/rangefinder.py
	$(IN_ENV) python bench/mcp_supervision.py
	$(IN_ENV) python bench/mcp_load.py
	$(IN_ENV) python bench/raycast.py
	$(IN_ENV) python bench/sim_step.py
	$(IN_ENV) python bench/sick_driver.py
	$(IN_ENV) python bench/nav_speed.py
	$(IN_ENV) python bench/nav_offline.py
	$(IN_ENV) python bench/local_module_cpu.py

# The full localization accuracy benchmark (issue 11's table): the simulated Pluto under the MCP on
# the shipped maps and generated ones, 200 m each, against the simulator's truth (about an hour).
.PHONY: bench-nav
bench-nav: build
	$(IN_ENV) python bench/nav_accuracy.py

# The slamModule under the MCP (issue 11's SLAM rows): loops with closure on the shipped and
# generated maps, the saved map scored against the true walls and localized in (about 40 minutes).
.PHONY: bench-slam
bench-slam: build
	$(IN_ENV) python bench/nav_slam.py

# Real robots' logs (issue 36): offline_nav --slam on the public SLAM benchmark's FR079 (its
# ground-truth relations) and MIT CSAIL (relative pose error against its reference trajectory), on
# one core, beside odometry and GMapping's published figures; then simulated logs on a shipped and
# generated maps against the truth.  The logs are not in the repository: SLAM_DATA is where they are
# (about two minutes).  It draws CSAIL's mapped walls over the reference's map in docs/.
SLAM_DATA ?= ../shared/data/slam-benchmark
.PHONY: bench-slam-real
bench-slam-real: build
	$(IN_ENV) python bench/slam_real.py --data $(SLAM_DATA) --png docs/slam-csail.png

# The avoidModule (issue 12): the avoidance computation for a 361-point scan and the laser scan in
# -> drive command out latency through a real avoid_module, beside a raw rclpy relay (about 1 minute);
# the guide's LaserAvoider and VectorMover in a kinematic simulation on generated worlds (4 minutes).
.PHONY: bench-avoid
bench-avoid: build
	$(IN_ENV) python bench/avoid_latency.py
	$(IN_ENV) python bench/guide_avoider.py

# The movement chain (issue 12's table): goto (32) and moveto (42) through motion/command on the
# shipped and generated maps, 20 random reachable goals each, against the simulator's truth: success,
# collisions, time, path over the shortest (a few hours; `python bench/nav_motion.py --pairs 5` for less).
.PHONY: bench-motion
bench-motion: build
	$(IN_ENV) python bench/nav_motion.py

# The chain among people (issue 38): moveto on the office and generated maps, empty and with 1, 3
# and 5 people crossing the robot's way, in one table: goals, contacts, least clearance, time lost.
.PHONY: bench-people
bench-people: build
	$(IN_ENV) python bench/nav_people.py

# The xmlServer (issue 15): var gets per second at 10 clients, and varpush latency beside a raw rclpy
# subscriber to the same stream in the same run (about a minute).
.PHONY: bench-xml
bench-xml: build
	$(IN_ENV) python bench/xml_server.py

# The VisionModule's operators (issue 14): ImageWriter and ImagePublisher frames per second at 320x240
# and 640x480 beside a raw cv2.imwrite loop and a raw rclpy sensor_msgs/Image publisher (about 30 s).
.PHONY: bench-vision
bench-vision: build
	$(IN_ENV) python bench/vision.py

# The soak (issue 16; not part of `make test`): the whole simulated Pluto under the MCP for SOAK_SECONDS
# while a chaos driver SIGKILLs, SIGSTOPs and SIGTERMs a random module every ~10 s; it reports restarts,
# time to Run after each kill, orphans, the MCP's memory, a counted queue-mode stream and the Pose error.
SOAK_SECONDS ?= 600
.PHONY: soak
soak: build
	$(IN_ENV) python bench/soak.py --seconds $(SOAK_SECONDS)

# The robot's footprint (issue 39; not a test, about 5 minutes): config/pluto driving a fixed route, per
# process CPU and PSS beside a raw rclpy baseline (default executor and EventsExecutor) in the same run.
.PHONY: bench-footprint
bench-footprint: build
	$(IN_ENV) python bench/footprint.py

# Two hosts (issue 16; needs root): network namespaces joined by a veth pair, the simulated Pluto
# under one MCP on "robot", a client under its own MCP on "desktop", the link cut for 10 s
# (src/wurde_mcp/test/test_two_hosts.py; about 2 minutes).  DDS stays on that link.
.PHONY: two-hosts
two-hosts: build
	cd src/wurde_mcp && WURDE_TWO_HOSTS=1 ../../$(IN_ENV) python -m pytest -v -s -p no:cacheprovider \
		test/test_two_hosts.py

# Fuzz campaigns (issue 16; not part of `make test`, which replays the kept corpus): atheris over every
# codec, XML reader, carmen.ini and the xmlServer's parser, FUZZ_SECONDS each (27 targets).
FUZZ_SECONDS ?= 30
.PHONY: fuzz
fuzz: build
	$(IN_ENV) pip install --quiet -r fuzz/requirements.txt
	$(IN_ENV) python fuzz/run.py --seconds $(FUZZ_SECONDS)

# The unit lane (issue 42): every package's tests that need neither DDS nor other processes, in
# about a minute.  `make test` (the README's test command, and CI's) still runs everything.
.PHONY: test-fast lint
test-fast: build
	tools/test_fast.sh

# ruff (ruff.toml) on the whole tree and mypy (mypy.ini) on every package's code, the benchmarks
# and the tools; `make test` runs it first.
lint: build
	tools/lint.sh
