"""A module that owes work after Quit (a slamModule saves its map, Pluto 7.2: "one should wait")
asks for the time with ``CommsManager.set_quit_time``; the MCP then waits that long before its
signals, where a module that asked nothing is escalated after the usual ~2 s grace.

Both workers below work 4 s after Quit, longer than the default escalation lets them (SIGKILL
comes 4 s after the Quit): the one that asked for 30 s ends cleanly having saved, the other is cut
off by the signals.
"""

from __future__ import annotations

import pathlib
import re
import signal
import time

from mcp_fixture import NOTICED, start_mcp, wait_file, wait_output, worker, write_config
from wurde_core import StatusMode
from wurde_mcp.supervisor import CMD_STOP, START_TIMEOUT_S


def test_the_mcp_waits_the_quit_time_a_module_asked_for(tmp_path, table) -> None:
    config, mappings = write_config(tmp_path, worker('Saver', extra='-w 4 -q 30')
                                    + worker('Hasty', extra='-w 4'))
    with start_mcp(tmp_path, config, mappings, '-a') as mcp:
        table.until(lambda r: all(x['status'] == StatusMode.ACTIVE for x in r.values()), 'both active')
        assert table.heartbeat_info('Saver').quit_time.get_value() == 30.0
        assert table.heartbeat_info('Hasty').quit_time.get_value() == 0.0
        stopped_at = time.monotonic()
        table.command(CMD_STOP, 'Saver')
        table.command(CMD_STOP, 'Hasty')
        saver = wait_output(mcp, NOTICED.format(name='Saver'), since=stopped_at, timeout=60)
        hasty = wait_output(mcp, NOTICED.format(name='Hasty'), since=stopped_at, timeout=60)
    logs = tmp_path / 'mcp-modules'
    wait_file(logs / 'Saver.log', 'saved')
    assert saver['code'] == '0', (logs / 'Saver.log').read_text()
    assert hasty['code'] != '0'
    hasty_run = _last_run(logs / 'Hasty.log')         # not its registration run's (-r)
    assert 'saving' in hasty_run and 'saved' not in hasty_run, hasty_run


def _last_run(log: pathlib.Path) -> str:
    """The part of a module's log written by its last process (after its last start line; the
    MCP's lines of its stop, ``--- SIGINT ...``, are part of it)."""
    return re.split(r'^--- \d{4}-\d\d-\d\d [\d:]+ start: .*$', log.read_text(), flags=re.M)[-1]


def test_a_quit_nobody_could_hear_yet_is_told_again_once_they_can(tmp_path) -> None:
    """The MCP ends while a module is still starting (its command channel has no reader yet, as
    right after a start on a loaded machine): the Quit reached no one, so the module's grace
    starts with the first Quit it can hear, and it ends cleanly, not by the SIGINT that would
    have come 2 s after the first Quit."""
    config, mappings = write_config(tmp_path, worker('Late', extra='-d 2.5'))
    with start_mcp(tmp_path, config, mappings, '-a') as mcp:
        wait_output(mcp, r'MCP: started Late')
        mcp.process.send_signal(signal.SIGINT)
        ended = wait_output(mcp, r'MCP: Late ended (?P<after>[0-9.]+) s after Quit \(exit code (?P<code>-?\d+); '
                            r'(?P<readers>\d+) readers', timeout=60)
    log = (tmp_path / 'mcp-modules' / 'Late.log').read_text()
    assert ended['readers'] == '0'
    assert ended['code'] == '0' and float(ended['after']) > 2.0, log
    assert '--- SIGINT' not in log, log


def test_a_module_asleep_before_it_can_hear_is_stopped_without_a_quit(tmp_path) -> None:
    """A module that sleeps before it makes its node (waiting for a device, say) makes no
    progress: after 5 s of that (DEAF_WAIT_S) its stop begins without a Quit it could hear, and
    the MCP does not wait out the 30 s a starting module is given."""
    config, mappings = write_config(tmp_path, worker('Sleeper', extra='-d 120'))
    with start_mcp(tmp_path, config, mappings, '-a') as mcp:
        wait_output(mcp, r'MCP: started Sleeper')
        mcp.process.send_signal(signal.SIGINT)
        wait_output(mcp, r'MCP: Sleeper never came to hear its Quit \((?P<since>[0-9.]+) s after its start\)',
                    timeout=60)
        ended = wait_output(mcp, r'MCP: Sleeper ended (?P<after>[0-9.]+) s after Quit \(exit code (?P<code>-?\d+); '
                            r'(?P<readers>\d+) readers', timeout=60)
    log = (tmp_path / 'mcp-modules' / 'Sleeper.log').read_text()
    assert ended['readers'] == '0'
    assert 5.0 <= float(ended['after']) < START_TIMEOUT_S, log
    assert '--- SIGINT' in log, log
