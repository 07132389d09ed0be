"""`make demo`: the main job of the workspace as it stands.

Runs the WURDE Programming Guide's first programs, FooServer and FooClient (wurde_core's
``foo_server`` and ``foo_client``), as two ROS 2 processes found the way `ros2 run` finds them
(lib/<package>/<executable> under the ament prefixes), shows what the client receives for a few
seconds, then stops both with SIGINT as a user would.  When the simulated robot exists it takes
over as the main job.  DDS stays on loopback (env.sh sets ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST).
"""

from __future__ import annotations

import os
import pathlib
import signal
import subprocess
import sys
import time

DEMO_SECONDS = 5.0


def find_executable(package: str, name: str) -> str:
    """``lib/<package>/<name>`` under the first ament prefix that has it (as `ros2 run` does)."""
    for prefix in os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep):
        path = pathlib.Path(prefix) / 'lib' / package / name
        if path.is_file() and os.access(path, os.X_OK):
            return str(path)
    raise SystemExit(f'demo: {package} {name} not found; run `make build` first')


def main() -> int:
    if os.environ.get('ROS_AUTOMATIC_DISCOVERY_RANGE') != 'LOCALHOST':
        raise SystemExit('demo: DDS must stay on loopback; run through `make demo` or env.sh')
    print(f'demo: ROS_DOMAIN_ID={os.environ.get("ROS_DOMAIN_ID")}, discovery on loopback only; '
          f'FooServer and FooClient for {DEMO_SECONDS:.0f} s', flush=True)
    client = subprocess.Popen([sys.executable, find_executable('wurde_core', 'foo_client')])
    server = subprocess.Popen([sys.executable, find_executable('wurde_core', 'foo_server')])
    codes = []
    try:
        time.sleep(DEMO_SECONDS)
    finally:
        for process in (server, client):
            if process.poll() is None:
                process.send_signal(signal.SIGINT)
        for process in (server, client):
            try:
                codes.append(process.wait(timeout=15))
            except subprocess.TimeoutExpired:
                process.kill()
                codes.append(process.wait())
    ok = all(code == 0 for code in codes)
    print('demo: both modules stopped cleanly' if ok else f'demo: exit codes {codes}')
    return 0 if ok else 1


if __name__ == '__main__':
    sys.exit(main())
