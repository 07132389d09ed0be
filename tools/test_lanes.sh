#!/usr/bin/env bash
# `make test`'s colcon test: every package's tests in two lanes at once, for the 2-core machine
# that must finish within 20 minutes.  A package's tests need its dependencies built, not tested,
# so colcon's test ordering is dropped (COLCON_FEATURE_FLAGS=drop_test_deps); the lanes are
# balanced by measured test times (wurde_drivers ~8.5 min, wurde_mcp ~5.5 min and wurde_core ~1 min
# in one lane; every other package, pluto_motion ~11.5 min and pluto_nav ~2.5 min the largest, in
# the other).  A package added later joins the first lane.  Arguments go to `colcon test`.
set -uo pipefail
cd "$(dirname "$0")/.."
second=(wurde_core wurde_drivers wurde_mcp)
mapfile -t all < <(tools/in_env.sh colcon list --names-only)
first=()
for package in "${all[@]}"; do
  [[ " ${second[*]} " == *" $package "* ]] || first+=("$package")
done

lane() {  # lane NAME PACKAGE...: one colcon test, its own log directory
  local name=$1
  shift
  COLCON_FEATURE_FLAGS=drop_test_deps tools/in_env.sh colcon --log-base "log/test-$name" test \
    --executor sequential "${COLCON_ARGS[@]}" --packages-select "$@"
}

COLCON_ARGS=("$@")
lane first "${first[@]}" & first_pid=$!
lane second "${second[@]}" & second_pid=$!
wait "$first_pid"; first_rc=$?
wait "$second_pid"; second_rc=$?
exit $(( first_rc ? first_rc : second_rc ))
