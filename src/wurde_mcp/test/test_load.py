"""No false zombies under load, and a real hang still caught in time (short form of
bench/mcp_load.py).

CPU burners fill both cores while the MCP watches modules at TTL 1 s: no module may be declared
a zombie, and a module stopped with SIGSTOP must be noticed within TTL + 0.3 s — measured with
the MCP's own monotonic timestamps.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time

from mcp_fixture import NOTICED, start_mcp, wait_output, worker, write_config
from wurde_core import StatusMode

MODULES = [f'L{i}' for i in range(6)]
BURNERS = 2
LOAD_S = 15.0
TTL_S = 1.0


def test_load_makes_no_false_zombie_and_a_sigstop_is_caught_in_time(tmp_path, table) -> None:
    config, mappings = write_config(tmp_path, ''.join(worker(name) for name in MODULES))
    burners: list[subprocess.Popen[bytes]] = []
    with start_mcp(tmp_path, config, mappings, '-a') as mcp:
        try:
            table.until(lambda r: all(x['status'] == StatusMode.ACTIVE for x in r.values()),
                        'all active', timeout=90)
            burners = [subprocess.Popen([sys.executable, '-c', 'while True: pass'])
                       for _ in range(BURNERS)]
            end = time.monotonic() + LOAD_S
            rows = table.refresh()
            while time.monotonic() < end:  # watch the table for the whole load period
                rows = table.refresh()
                assert all(x['status'] == StatusMode.ACTIVE and x['restarts'] == 0
                           for x in rows.values()), f'a module fell under load: {rows}'
                table.manager.wait(0.1)
            hung = rows['L0']['pid']
            stopped_at = time.monotonic()
            os.kill(hung, signal.SIGSTOP)
            seen = wait_output(mcp, NOTICED.format(name='L0'), timeout=30, since=stopped_at)
            caught = float(seen['at']) - stopped_at
            assert seen['code'] is None  # a zombie, not an exit
            assert caught <= TTL_S + 0.3, f'SIGSTOP caught after {caught:.3f} s'
        finally:
            for burner in burners:
                burner.kill()
                burner.wait()
        rows = table.until(lambda r: r['L0']['pid'] != hung
                           and r['L0']['status'] == StatusMode.ACTIVE, 'L0 replaced')
        others = [name for name in MODULES if name != 'L0']
        assert all(rows[n]['restarts'] == 0 for n in others), rows
        false = [line for line in (mcp.stderr + mcp.stdout).splitlines()
                 if re.search(r'MCP: L[1-9] missed its TTL', line)]
        assert false == [], f'false zombies: {false}'
