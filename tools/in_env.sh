#!/usr/bin/env bash
# Run one command inside the workspace environment (env.sh): used by the Makefile.
set -eo pipefail
# shellcheck disable=SC1091
. "$(cd "$(dirname "$0")/.." && pwd)/env.sh"
exec "$@"
