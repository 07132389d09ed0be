#!/usr/bin/env bash
# `make lint` (issue 42): ruff on the whole tree (ruff.toml), then mypy (mypy.ini) on every
# package's code, the benchmarks and the tools.  Run by `make test` before the tests.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
python=.venv/bin/python
"$python" -m ruff check --no-cache src bench tools
"$python" -m mypy --cache-dir build/mypy-cache \
  src/wurde_interfaces/wurde_idl src/wurde_interfaces/wurde_testing src/wurde_core/wurde_core \
  src/wurde_mcp/wurde_mcp src/wurde_drivers/wurde_drivers src/pluto_nav/pluto_nav \
  src/pluto_motion/pluto_motion
"$python" -m mypy --cache-dir build/mypy-cache bench
"$python" -m mypy --cache-dir build/mypy-cache tools
