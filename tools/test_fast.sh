#!/usr/bin/env bash
# `make test-fast`: the unit lane, every package's tests that need neither DDS nor other processes
# (pytest --fast, wurde_testing.fixtures), one pytest run per package, two at a time (the 2-core
# machine).  Not the README's test command: `make test` runs everything.
set -uo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

one() {  # one PACKAGE PATH: its fast tests, the output kept for the summary
  local package=$1 directory=$2 status=0
  [ -d "$directory/test" ] || return 0
  (cd "$directory" && "$root/tools/in_env.sh" python -m pytest -q -p no:cacheprovider --fast test) \
    > "$out/$package.log" 2>&1 || status=$?
  (( status == 5 )) && status=0      # 5: every test of the package needs DDS or processes
  echo "$status" > "$out/$package.rc"
}
export -f one
export root out
tools/in_env.sh colcon list | awk '{print $1, $2}' | xargs -P 2 -n 2 bash -c 'one "$0" "$1"'
rc=0
for log in "$out"/*.log; do
  package=$(basename "$log" .log)
  echo "== $package: $(tail -n 1 "$log")"
  status=$(cat "$out/$package.rc")
  if (( status )); then
    cat "$log"
    (( rc )) || rc=$status
  fi
done
exit "$rc"
