"""The import-rule checker used by every package's tests, and wurde_interfaces' own imports."""

from __future__ import annotations

import pathlib

from wurde_testing.imports import violations

SOURCE = pathlib.Path(__file__).resolve().parents[1]


def test_wurde_interfaces_python_imports_nothing_else_of_ours() -> None:
    for module in ('wurde_idl', 'wurde_testing'):
        assert violations('wurde_interfaces', SOURCE / module) == []


def test_checker_reports_a_forbidden_import(tmp_path: pathlib.Path) -> None:
    (tmp_path / 'ok.py').write_text('import rclpy\nfrom wurde_idl import load\n')
    (tmp_path / 'bad.py').write_text('import os\nfrom wurde_mcp.supervisor import Mcp\n')
    assert violations('wurde_core', tmp_path) == [
        f'{tmp_path / "bad.py"}: imports wurde_mcp (package wurde_mcp)']


def test_pluto_motion_may_use_the_loc_proxy_but_not_drivers(tmp_path: pathlib.Path) -> None:
    (tmp_path / 'm.py').write_text('from pluto_nav.loc_proxy import LocProxy\nimport wurde_drivers\n')
    assert violations('pluto_motion', tmp_path) == [
        f'{tmp_path / "m.py"}: imports wurde_drivers (package wurde_drivers)']
