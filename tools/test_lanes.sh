#!/usr/bin/env bash
# `make test`'s colcon test: every package's tests in four lanes at once, for the 2-core machine
# that must finish within 20 minutes.  The tests wait on robots that move in real time far more
# than they compute (test_guide_avoider: 43% of one core over its run), so more lanes than cores
# cut the wall time; the tests hold on a loaded machine by design (they wait on events with
# deadlines).  A package's tests need its dependencies built, not tested, so colcon's test
# ordering is dropped (COLCON_FEATURE_FLAGS=drop_test_deps).
#
# The lanes are balanced by measured test times (a fresh-clone run with three lanes, 2026-12-06:
# pluto_motion 16.4 min, which made the whole `make test` 20 min; wurde_drivers 11.5; wurde_mcp
# 8.7; pluto_nav 5.1; wurde_core 1).  pluto_motion is split in two runs of its own pytest: its
# four longest files (about 6 min: a whole robot each, or a calibration drive) and the rest; each
# writes its own JUnit report (colcon test-result and tools/test_summary.py read them all).  The
# lane of every other package is where a package added later goes.  wurde_drivers' README examples
# (test_readme.py, about 80 s) run after pluto_nav, with their own report (build/test-drivers-readme):
# a fresh clone on 2026-12-06 had wurde_drivers' lane at 15.9 min, and with them moved out 14.3,
# the lanes of pluto_motion's long files and pluto_nav 12.8.  They run after the other packages'
# since 2026-12-07: a fresh clone took 20 min 10 s with the lanes at 15:56 (pluto_motion's long
# files 7:31, pluto_nav 7:05, the README examples), 14:43, 15:05 (wurde_drivers) and 13:43 (the
# others, wurde_mcp 11:39).  Arguments go to `colcon test`.
set -uo pipefail
cd "$(dirname "$0")/.."
long_files=(test/test_demo.py test/test_odometry_calibration.py test/test_guide_avoider.py
            test/test_navigator.py)
placed=(pluto_motion pluto_nav wurde_core wurde_drivers)
mapfile -t all < <(tools/in_env.sh colcon list --names-only)
rest=()
for package in "${all[@]}"; do
  [[ " ${placed[*]} " == *" $package "* ]] || rest+=("$package")
done
# Two pytest runs of one package share its build directory: no pytest cache for them.  colcon
# takes a --pytest-args value that starts with '-' only after a space.
no_cache=(' -p' 'no:cacheprovider')
ignore_long=()
for file in "${long_files[@]}"; do
  ignore_long+=(" --ignore=$file")
done

run() {  # run NAME ARG...: one colcon test with its own log directory; ARGs go to colcon test
  local name=$1
  shift
  COLCON_FEATURE_FLAGS=drop_test_deps tools/in_env.sh colcon --log-base "log/test-$name" test \
    --executor sequential "${COLCON_ARGS[@]}" "$@"
}

lane() {  # lane CMD...: the commands (each one word, a function) in turn; the first failure's status
  local rc=0 cmd
  for cmd in "$@"; do
    "$cmd" || { local status=$?; (( rc )) || rc=$status; }
  done
  return "$rc"
}

long_motion() {
  run motion-long --packages-select pluto_motion --test-result-base build/test-motion-long \
    --pytest-args "${no_cache[@]}" "${long_files[@]}"
}
rest_of_motion() {
  run motion-rest --packages-select pluto_motion --pytest-args "${no_cache[@]}" "${ignore_long[@]}"
}
nav() { run nav --packages-select pluto_nav; }
core() { run core --packages-select wurde_core; }
drivers() {
  run drivers --packages-select wurde_drivers --pytest-args "${no_cache[@]}" ' --ignore=test/test_readme.py'
}
drivers_readme() {
  run drivers-readme --packages-select wurde_drivers --test-result-base build/test-drivers-readme \
    --pytest-args "${no_cache[@]}" test/test_readme.py
}
others() { run rest --packages-select "${rest[@]}"; }

COLCON_ARGS=("$@")
pids=()
lane long_motion nav & pids+=($!)
lane rest_of_motion core & pids+=($!)
lane drivers & pids+=($!)
lane others drivers_readme & pids+=($!)
rc=0
for pid in "${pids[@]}"; do
  wait "$pid" || { status=$?; (( rc )) || rc=$status; }
done
exit "$rc"
