"""Binaries are found by absolute path, bin-directory, the ament index, then PATH."""

from __future__ import annotations

import pathlib

import pytest

from wurde_mcp.binaries import find_binary


def make(path: pathlib.Path) -> pathlib.Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text('#!/bin/sh\n')
    path.chmod(0o755)
    return path


def test_search_order(tmp_path: pathlib.Path, monkeypatch: pytest.MonkeyPatch) -> None:
    absolute = make(tmp_path / 'abs' / 'tool')
    assert find_binary(str(absolute)) == str(absolute)
    assert find_binary(str(tmp_path / 'abs' / 'missing')) is None
    in_bin = make(tmp_path / 'bin' / 'tool')
    prefix = tmp_path / 'prefix'
    in_index = make(prefix / 'lib' / 'some_pkg' / 'tool')
    on_path = make(tmp_path / 'path' / 'tool')
    monkeypatch.setenv('AMENT_PREFIX_PATH', str(prefix))
    monkeypatch.setenv('PATH', str(tmp_path / 'path'))
    assert find_binary('tool', str(tmp_path / 'bin')) == str(in_bin)
    assert find_binary('tool') == str(in_index)
    assert find_binary('some_pkg/tool') == str(in_index)
    in_index.unlink()
    assert find_binary('tool') == str(on_path)
    assert find_binary('nowhere') is None


def test_the_real_foo_server_is_found() -> None:
    found = find_binary('wurde_core/foo_server')
    assert found is not None and found.endswith('lib/wurde_core/foo_server')
