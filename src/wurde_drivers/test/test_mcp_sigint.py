"""SIGINT to the MCP ends it and every module of the simulated robot within 3 s (issue 17).

``config/sim`` under the MCP, every module active; then one SIGINT to the MCP (as ``kill -INT``
or a supervisor would send; a terminal's Ctrl-C reaches the whole process group).  The MCP tells
every module to Quit at once; a module told to Quit skips waiting for its goodbye's
acknowledgement (which took each module its full second before).  Each module's end is seen
through a pidfd, so the figure is the exit itself, not a poll interval.
"""

from __future__ import annotations

import os
import select
import signal
import time

from sim_fixture import sim_config
from wurde_mcp.control import connect, read_table
from wurde_testing import ChildProcess, find_executable

MODULES = {'PlutoBase', 'PlutoLaser', 'PlutoWrist', 'PlutoDMU', 'PlutoGPS'}
BOUND_S = 3.0


def test_sigint_ends_the_mcp_and_all_its_modules_within_3_s(ros_domain: int, tmp_path) -> None:
    sim_config(tmp_path)
    env = dict(os.environ, WURDE_CONFIG_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path))
    with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', str(tmp_path / 'mcp-config.xml'),
                       '-m', str(tmp_path / 'mcp-mappings.xml'), '-a'], env=env) as mcp:
        mcp.expect('MCP ready', timeout=90)
        manager, control = connect('SigintTest', wait_s=60)
        try:
            deadline = time.monotonic() + 120
            while True:
                rows = read_table(manager, control) or []
                if {r['name'] for r in rows if r['status'] == 'ACTIVE' and r['state'] == 'RUN'} == MODULES:
                    break
                assert time.monotonic() < deadline, f'not all active and running: {rows}'
        finally:
            manager.clean_up()
        pids = {r['name']: r['pid'] for r in rows}
        fds = {os.pidfd_open(pid): name for name, pid in pids.items()}
        try:
            sent = time.monotonic()
            mcp.process.send_signal(signal.SIGINT)
            ended: dict[str, float] = {}
            while len(ended) < len(fds) and time.monotonic() - sent < 30:
                ready, _, _ = select.select(list(set(fds) - {fd for fd, n in fds.items() if n in ended}), [], [],
                                            1.0)
                for fd in ready:
                    ended[fds[fd]] = time.monotonic() - sent
            code = mcp.process.wait(30)
            mcp_s = time.monotonic() - sent
        finally:
            for fd in fds:
                os.close(fd)
    assert code == 0, mcp.stderr
    assert set(ended) == MODULES, f'still running 30 s after SIGINT: {MODULES - set(ended)}'
    slowest = max(ended.values())
    print(f'modules ended {sorted(ended.items(), key=lambda kv: kv[1])}; MCP {mcp_s:.2f} s')
    assert slowest <= BOUND_S and mcp_s <= BOUND_S, \
        f'modules ended after {ended} s, the MCP after {mcp_s:.2f} s'
