"""`make demo`: the main job of the workspace as it stands.

Runs a supplier and a consumer of a WURDE interface as two separate ROS 2 processes, found the way
`ros2 run` finds them (lib/<package>/<executable> under the ament prefixes), and shows what the
consumer receives.  Today that is the example Thermometer interface, generated from XML at build
time; as the suite grows this becomes the FooServer/FooClient pair and then the simulated robot.
DDS stays on loopback (env.sh sets ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST).
"""

from __future__ import annotations

import os
import pathlib
import subprocess
import sys


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
    package = 'wurde_example_thermometer'
    print(f'demo: ROS_DOMAIN_ID={os.environ.get("ROS_DOMAIN_ID")}, discovery on loopback only')
    consumer = subprocess.Popen([sys.executable, find_executable(package, 'thermometer_consumer'),
                                 '--count', '20'])
    supplier = subprocess.Popen([sys.executable, find_executable(package, 'thermometer_supplier'),
                                 '--count', '20', '--rate', '10'])
    try:
        code = consumer.wait(timeout=60)
    finally:
        for process in (consumer, supplier):
            if process.poll() is None:
                process.terminate()
            process.wait(timeout=10)
    print('demo: done' if code == 0 else f'demo: consumer failed ({code})')
    return code


if __name__ == '__main__':
    sys.exit(main())
