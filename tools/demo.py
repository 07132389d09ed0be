"""`make demo`: the main job — the simulated Pluto, brought up by the MCP, on a mission by place names.

1. The MCP (``wurde_mcp``'s ``mcp``) reads ``config/pluto/mcp-config.xml`` and starts the whole
   robot as supervised modules: the dummies (base, laser, wrist, DMU, GPS; odometry, laser and
   DMU noise on), the localModule and poseModule (Pluto 3 and 7) and the chain drive -> avoid ->
   motion (Pluto 4 and 6); they read ``sim-config.xml`` and ``map.xml`` from the config directory
   (``WURDE_CONFIG_DIR=config/pluto``).
2. The ``mission`` client (``pluto_motion``) sends the robot through named places of the map by
   moveto, shows live progress (goal, distance left, pose error against the simulator's truth,
   the modules' states), ends with a summary table and saves ``demo-output/mission.png``.
   Meanwhile ``record`` (``wurde_mcp``) writes every topic to ``demo-output/mission.mcap``.
3. The recorder and the MCP are stopped with SIGINT, which quits every module.

DDS stays on loopback (env.sh sets ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST). Options (for tests):
``--config-dir DIR`` another config directory, ``--output DIR`` where the plot goes,
``--places a,b,c`` other places.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import signal
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
MISSION_TIMEOUT_S = 900.0


def find_executable(package: str, name: str) -> str:
    """``lib/<package>/<name>`` under the first ament prefix that has it (as `ros2 run` does)."""
    for prefix in os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep):
        path = pathlib.Path(prefix) / 'lib' / package / name
        if path.is_file() and os.access(path, os.X_OK):
            return str(path)
    raise SystemExit(f'demo: {package} {name} not found; run `make build` first')


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--config-dir', default=str(ROOT / 'config' / 'pluto'))
    parser.add_argument('--output', default=str(ROOT / 'demo-output'))
    parser.add_argument('--places', default='', help='comma-separated place names (default: the mission\'s)')
    args = parser.parse_args()
    if os.environ.get('ROS_AUTOMATIC_DISCOVERY_RANGE') != 'LOCALHOST':
        raise SystemExit('demo: DDS must stay on loopback; run through `make demo` or env.sh')
    config_dir = pathlib.Path(args.config_dir).resolve()
    output = pathlib.Path(args.output).resolve()
    output.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, WURDE_CONFIG_DIR=str(config_dir), WURDE_DATA_DIR=str(output),
               WURDE_LOG_DIRECTORY=str(output))
    print(f'demo: ROS_DOMAIN_ID={os.environ.get("ROS_DOMAIN_ID")}, discovery on loopback only; '
          f'the MCP brings up the simulated Pluto from {config_dir}', flush=True)
    record = subprocess.Popen([sys.executable, find_executable('wurde_mcp', 'record'),
                               '-o', str(output / 'mission.mcap')], env=env, stdout=subprocess.DEVNULL)
    mcp = subprocess.Popen([sys.executable, find_executable('wurde_mcp', 'mcp'),
                            '-c', str(config_dir / 'mcp-config.xml'),
                            '-m', str(config_dir / 'mcp-mappings.xml'), '-a'], env=env)
    try:
        places = ['-P', args.places] if args.places else []
        mission = subprocess.run([sys.executable, find_executable('pluto_motion', 'mission'),
                                  '-O', str(output), *places], env=env, timeout=MISSION_TIMEOUT_S,
                                 check=False)
        mission_code = mission.returncode
    except subprocess.TimeoutExpired:
        print(f'demo: the mission took longer than {MISSION_TIMEOUT_S:.0f} s', flush=True)
        mission_code = 1
    finally:
        record_code = _stop(record)
        mcp_code = _stop(mcp)
    print(f'demo: mission exit {mission_code}, MCP exit {mcp_code}, record exit {record_code}; plot in '
          f'{output / "mission.png"}; every topic in {output / "mission.mcap"}; module logs in '
          f'{output / "mcp-modules"}', flush=True)
    return 0 if mission_code == 0 and mcp_code == 0 and record_code == 0 else 1


def _stop(process: subprocess.Popen) -> int:
    """SIGINT, then SIGKILL after a minute; the exit code."""
    if process.poll() is None:
        process.send_signal(signal.SIGINT)
    try:
        return process.wait(timeout=60)
    except subprocess.TimeoutExpired:
        process.kill()
        return process.wait()


if __name__ == '__main__':
    sys.exit(main())
