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

DDS stays on loopback (env.sh sets ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST). Options (``make demo
DEMO_ARGS="..."``): ``--time-scale X`` simulated seconds per wall second (the config is copied to
``<output>/config`` with its sim-config's ``time-scale`` set, and the MCP and its modules take their
time from the simulator's ``/clock``); ``--people N`` the crowded variant: the config copied there
with the first N of ``config/pluto-people``'s people walking the office (issue 38);
``--live [PORT]`` also serves every topic to Foxglove on
``ws://127.0.0.1:PORT`` (``live_view``, default 8765) while the mission runs; ``--config-dir DIR``
another config directory, ``--output DIR`` where the plot goes, ``--places a,b,c`` other places.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import shutil
import signal
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
#: The crowded variant's people (config/pluto-people: the same robot and office, with people).
CROWD = ROOT / 'config' / 'pluto-people' / 'sim-config.xml'
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
    parser.add_argument('--time-scale', type=float, default=None,
                        help='simulated seconds per wall second (default: the sim-config\'s)')
    parser.add_argument('--live', type=int, nargs='?', const=8765, default=None, metavar='PORT',
                        help='also serve every topic to Foxglove on ws://127.0.0.1:PORT (8765)')
    parser.add_argument('--people', type=int, default=0, metavar='N',
                        help=f'N of the people of {CROWD.relative_to(ROOT)} walk the office (default 0)')
    args = parser.parse_args()
    if os.environ.get('ROS_AUTOMATIC_DISCOVERY_RANGE') != 'LOCALHOST':
        raise SystemExit('demo: DDS must stay on loopback; run through `make demo` or env.sh')
    config_dir = pathlib.Path(args.config_dir).resolve()
    output = pathlib.Path(args.output).resolve()
    output.mkdir(parents=True, exist_ok=True)
    ros_args: list[str] = []
    if args.time_scale is not None and not args.time_scale > 0:
        raise SystemExit(f'demo: --time-scale must be above 0, not {args.time_scale}')
    if args.time_scale is not None or args.people:
        config_dir = prepared_config(config_dir, output / 'config', args.time_scale, args.people)
    if args.time_scale is not None:
        ros_args = ['--ros-args', '-p', 'use_sim_time:=true']
    env = dict(os.environ, WURDE_CONFIG_DIR=str(config_dir), WURDE_DATA_DIR=str(output),
               WURDE_LOG_DIRECTORY=str(output))
    print(f'demo: ROS_DOMAIN_ID={os.environ.get("ROS_DOMAIN_ID")}, discovery on loopback only; '
          f'the MCP brings up the simulated Pluto from {config_dir}', flush=True)
    record = subprocess.Popen([sys.executable, find_executable('wurde_mcp', 'record'),
                               '-o', str(output / 'mission.mcap')], env=env, stdout=subprocess.DEVNULL)
    live = (subprocess.Popen([sys.executable, find_executable('wurde_mcp', 'live_view'),
                              '-p', str(args.live)], env=env) if args.live is not None else None)
    mcp = subprocess.Popen([sys.executable, find_executable('wurde_mcp', 'mcp'),
                            '-c', str(config_dir / 'mcp-config.xml'),
                            '-m', str(config_dir / 'mcp-mappings.xml'), '-a', *ros_args], env=env)
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
        if live is not None:
            _stop(live)
        mcp_code = _stop(mcp)
    print(f'demo: mission exit {mission_code}, MCP exit {mcp_code}, record exit {record_code}; plot in '
          f'{output / "mission.png"}; every topic in {output / "mission.mcap"}; module logs in '
          f'{output / "mcp-modules"}', flush=True)
    return 0 if mission_code == 0 and mcp_code == 0 and record_code == 0 else 1


def prepared_config(source: pathlib.Path, target: pathlib.Path, time_scale: float | None,
                    people: int) -> pathlib.Path:
    """``source`` copied to ``target``, its sim-config's ``time-scale`` set (None: kept) and the
    first ``people`` ``<person>`` elements of :data:`CROWD` added to it.

    :raises SystemExit: more people than the crowded variant declares, or fewer than 0.
    """
    from lxml import etree
    parser = etree.XMLParser(resolve_entities=False, no_network=True)
    crowd = etree.parse(str(CROWD), parser).getroot().findall('person')
    if not 0 <= people <= len(crowd):
        raise SystemExit(f'demo: --people takes 0 to {len(crowd)} (the people of {CROWD}), not {people}')
    shutil.copytree(source, target, dirs_exist_ok=True)
    path = target / 'sim-config.xml'
    tree = etree.parse(str(path), parser)
    root = tree.getroot()
    if time_scale is not None:
        root.set('time-scale', repr(time_scale))
    for person in crowd[:people]:
        root.append(person)
    tree.write(str(path), xml_declaration=True, encoding='utf-8')
    return target


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
