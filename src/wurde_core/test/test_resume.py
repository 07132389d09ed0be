"""wurde_core.resume: the state file the MCP gives a module, read only on a restart."""

from __future__ import annotations

import json

import pytest
from wurde_core.heartbeat import RESTART_ENV
from wurde_core.resume import STATE_ENV, ResumeState


def test_a_module_started_by_hand_keeps_no_state(monkeypatch, tmp_path) -> None:
    monkeypatch.delenv(STATE_ENV, raising=False)
    kept = ResumeState()
    assert not kept.enabled
    assert kept.save({'x': 1.0}) is False
    assert kept.load() == (None, 'not started by an MCP')
    assert list(tmp_path.iterdir()) == []


def test_a_restart_gets_what_the_last_process_saved_and_a_first_start_does_not(monkeypatch, tmp_path) -> None:
    path = tmp_path / 'Base.resume'
    monkeypatch.setenv(STATE_ENV, str(path))
    monkeypatch.setenv(RESTART_ENV, '0')
    kept = ResumeState(every_s=60.0)
    assert kept.save({'x': 1.5, 'y': -2.0}) is True
    assert kept.save({'x': 9.0, 'y': 9.0}) is False            # not yet time to
    assert json.loads(path.read_text()) == {'x': 1.5, 'y': -2.0}
    assert kept.save({'x': 2.5, 'y': -2.0}, force=True) is True
    assert ResumeState().load() == (None, 'a first start')
    monkeypatch.setenv(RESTART_ENV, '3')
    state, why = ResumeState().load()
    assert state == {'x': 2.5, 'y': -2.0} and why.startswith('restart 3')
    assert not list(tmp_path.glob('*.tmp'))                      # replaced, not left half-written


@pytest.mark.parametrize('content, reason', [
    (None, 'no state saved by the last process'),
    ('{"x": 1.0', 'unreadable'),
    ('[1, 2]', 'not a JSON object'),
    (b'\xff\xfe', 'unreadable')])
def test_a_missing_or_bad_file_on_a_restart_is_said_not_raised(monkeypatch, tmp_path, content, reason) -> None:
    path = tmp_path / 'Base.resume'
    if isinstance(content, bytes):
        path.write_bytes(content)
    elif content is not None:
        path.write_text(content)
    monkeypatch.setenv(STATE_ENV, str(path))
    monkeypatch.setenv(RESTART_ENV, '1')
    state, why = ResumeState().load()
    assert state is None and reason in why and str(path) in why


def test_a_save_that_fails_is_kept_as_a_reason(monkeypatch, tmp_path) -> None:
    monkeypatch.setenv(STATE_ENV, str(tmp_path / 'no such directory' / 'Base.resume'))
    kept = ResumeState()
    assert kept.save({'x': 1.0}) is False
    assert kept.failure is not None and 'cannot save' in kept.failure
