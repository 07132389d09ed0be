"""`make demo`: the main job — the simulated Pluto robot, brought up by the MCP, driven round the office.

1. The MCP (``wurde_mcp``'s ``mcp``) reads ``config/sim/mcp-config.xml`` and starts every dummy
   (base, laser, wrist, DMU, GPS) as a supervised module; they read ``config/sim/sim-config.xml``
   from the config directory (``WURDE_CONFIG_DIR=config/sim``).
2. The ``tour`` client drives the robot through waypoints of the office map with its odometry and
   laser, printing what it sees, and saves a plot (map, path, last laser scan) as
   ``demo-output/tour.png``.
3. The MCP is stopped with SIGINT, which quits every module.

DDS stays on loopback (env.sh sets ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST). Options (for tests):
``--config-dir DIR`` another config directory, ``--output DIR`` where the plot goes.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import signal
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
TOUR_TIMEOUT_S = 600.0


def find_executable(package: str, name: str) -> str:
    """``lib/<package>/<name>`` under the first ament prefix that has it (as `ros2 run` does)."""
    for prefix in os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep):
        path = pathlib.Path(prefix) / 'lib' / package / name
        if path.is_file() and os.access(path, os.X_OK):
            return str(path)
    raise SystemExit(f'demo: {package} {name} not found; run `make build` first')


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--config-dir', default=str(ROOT / 'config' / 'sim'))
    parser.add_argument('--output', default=str(ROOT / 'demo-output'))
    args = parser.parse_args()
    if os.environ.get('ROS_AUTOMATIC_DISCOVERY_RANGE') != 'LOCALHOST':
        raise SystemExit('demo: DDS must stay on loopback; run through `make demo` or env.sh')
    config_dir = pathlib.Path(args.config_dir).resolve()
    output = pathlib.Path(args.output).resolve()
    output.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, WURDE_CONFIG_DIR=str(config_dir), WURDE_DATA_DIR=str(output),
               WURDE_LOG_DIRECTORY=str(output))
    print(f'demo: ROS_DOMAIN_ID={os.environ.get("ROS_DOMAIN_ID")}, discovery on loopback only; '
          f'the MCP brings up the dummy Pluto from {config_dir}', flush=True)
    mcp = subprocess.Popen([sys.executable, find_executable('wurde_mcp', 'mcp'),
                            '-c', str(config_dir / 'mcp-config.xml'),
                            '-m', str(config_dir / 'mcp-mappings.xml'), '-a'], env=env)
    try:
        tour = subprocess.run([sys.executable, find_executable('wurde_drivers', 'tour'),
                               '-p', str(output / 'tour.png')], env=env, timeout=TOUR_TIMEOUT_S,
                              check=False)
        tour_code = tour.returncode
    except subprocess.TimeoutExpired:
        print(f'demo: the tour took longer than {TOUR_TIMEOUT_S:.0f} s', flush=True)
        tour_code = 1
    finally:
        if mcp.poll() is None:
            mcp.send_signal(signal.SIGINT)
        try:
            mcp_code = mcp.wait(timeout=60)
        except subprocess.TimeoutExpired:
            mcp.kill()
            mcp_code = mcp.wait()
    print(f'demo: tour exit {tour_code}, MCP exit {mcp_code}; plot in {output / "tour.png"}; '
          f'module logs in {output / "mcp-modules"}', flush=True)
    return 0 if tour_code == 0 and mcp_code == 0 else 1


if __name__ == '__main__':
    sys.exit(main())
