"""wurde_core imports only what docs/design.md's "Who may import whom" allows."""

import pathlib

import pytest
from wurde_testing.imports import violations

SOURCE = pathlib.Path(__file__).resolve().parents[1] / 'wurde_core'


def test_imports_follow_the_package_rules() -> None:
    assert SOURCE.is_dir()
    assert violations('wurde_core', SOURCE) == []


@pytest.mark.process
def test_wurde_core_imports_without_a_sourced_workspace(tmp_path: pathlib.Path) -> None:
    """No RobotObject class is bound at import time: with wurde_core and wurde_idl on the path but
    no workspace sourced, importing works and using an interface says what is missing."""
    import os
    import subprocess
    import sys

    import wurde_core
    import wurde_idl
    path = os.pathsep.join(str(pathlib.Path(m.__file__).resolve().parents[1])
                           for m in (wurde_core, wurde_idl))
    env = {k: v for k, v in os.environ.items()
           if k not in ('AMENT_PREFIX_PATH', 'COLCON_PREFIX_PATH', 'CMAKE_PREFIX_PATH')}
    env['PYTHONPATH'] = path
    env['AMENT_PREFIX_PATH'] = sys.prefix
    script = (
        'import wurde_core, wurde_core.naming, wurde_core.interfaces\n'
        'from wurde_core import Logger, UnknownInterfaceError\n'
        'from wurde_core.wrappers import ObstacleAvoider\n'
        'print(wurde_core.naming.topic("Localization/Dead-Reckoning", "data"))\n'
        'print(hasattr(wurde_core.interfaces, "Foo"))\n'
        'try:\n'
        '    Logger("x")\n'
        'except UnknownInterfaceError as exc:\n'
        '    print("refused:", exc)\n')
    result = subprocess.run([sys.executable, '-c', script], env=env, cwd=tmp_path,
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert lines[0] == '/wurde/Localization/w__Dead_2DReckoning/data'
    assert lines[1] == 'False'
    assert lines[2].startswith('refused: unknown interface "LoggerTransport"')
