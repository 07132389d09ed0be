#!/usr/bin/env bash
# `make test`'s colcon test: every package's tests in three lanes at once, for the 2-core machine
# that must finish within 20 minutes.  The tests wait on robots that move in real time far more
# than they compute (test_guide_avoider: 43% of one core over its run), so three lanes on two
# cores cut the wall time; the tests hold on a loaded machine by design (they wait on events with
# deadlines).  A package's tests need its dependencies built, not tested, so colcon's test
# ordering is dropped (COLCON_FEATURE_FLAGS=drop_test_deps).  The lanes are balanced by measured
# test times (a fresh-clone run, r85): pluto_motion ~14.5 min alone; wurde_drivers ~9.5 min with
# wurde_core ~1 min; wurde_mcp ~7 min with pluto_nav ~3 min and every other package, which is
# where a package added later goes.  Arguments go to `colcon test`.
set -uo pipefail
cd "$(dirname "$0")/.."
motion=(pluto_motion)
drivers=(wurde_core wurde_drivers)
mapfile -t all < <(tools/in_env.sh colcon list --names-only)
rest=()
for package in "${all[@]}"; do
  [[ " ${motion[*]} ${drivers[*]} " == *" $package "* ]] || rest+=("$package")
done

lane() {  # lane NAME PACKAGE...: one colcon test, its own log directory
  local name=$1
  shift
  COLCON_FEATURE_FLAGS=drop_test_deps tools/in_env.sh colcon --log-base "log/test-$name" test \
    --executor sequential "${COLCON_ARGS[@]}" --packages-select "$@"
}

COLCON_ARGS=("$@")
pids=()
lane motion "${motion[@]}" & pids+=($!)
lane drivers "${drivers[@]}" & pids+=($!)
lane rest "${rest[@]}" & pids+=($!)
rc=0
for pid in "${pids[@]}"; do
  wait "$pid" || { status=$?; (( rc )) || rc=$status; }
done
exit "$rc"
