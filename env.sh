# Source this file (`source env.sh`) for a shell in which the workspace's executables run by hand:
# the virtual environment with ROS 2 Jazzy, the built workspace (install/setup.bash) and DDS kept on
# loopback.  `make build` creates both; this file only activates them.  It also serves the Makefile.
#
# ROS_DOMAIN_ID defaults to 42; set it before sourcing to choose another (0-101).  Discovery never
# leaves the machine: ROS_AUTOMATIC_DISCOVERY_RANGE is always LOCALHOST here.

_wurde_root=$(cd "$(dirname "${BASH_SOURCE[0]:-$0}")" && pwd)

if [ -f "$_wurde_root/.venv/bin/activate" ]; then
  # shellcheck disable=SC1091
  . "$_wurde_root/.venv/bin/activate"
  # The ROS wheels install an ament prefix into the venv itself.
  case ":${AMENT_PREFIX_PATH:-}:" in
    *":$VIRTUAL_ENV:"*) ;;
    *) export AMENT_PREFIX_PATH="$VIRTUAL_ENV${AMENT_PREFIX_PATH:+:$AMENT_PREFIX_PATH}" ;;
  esac
  case ":${CMAKE_PREFIX_PATH:-}:" in
    *":$VIRTUAL_ENV:"*) ;;
    *) export CMAKE_PREFIX_PATH="$VIRTUAL_ENV${CMAKE_PREFIX_PATH:+:$CMAKE_PREFIX_PATH}" ;;
  esac
else
  echo "env.sh: no .venv in $_wurde_root yet; run 'make build' first" >&2
fi

if [ -f "$_wurde_root/install/setup.bash" ]; then
  # colcon's setup scripts read unset variables; relax -u around them for callers using set -u.
  case $- in *u*) _wurde_u=1; set +u ;; *) _wurde_u= ;; esac
  # shellcheck disable=SC1091
  . "$_wurde_root/install/setup.bash"
  [ -n "$_wurde_u" ] && set -u
  unset _wurde_u
fi

export ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST
export ROS_DOMAIN_ID="${ROS_DOMAIN_ID:-42}"
export WURDE_ROOT="$_wurde_root"
unset _wurde_root
