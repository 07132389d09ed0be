"""The manual's MCP example (docs/mcp.md) (config/foo) runs as written: FooServer and FooClient come up."""

from __future__ import annotations

import os
import pathlib
import re
import time

from mcp_fixture import Table
from wurde_core import StatusMode
from wurde_testing import ChildProcess
from wurde_testing.manual import section

ROOT = pathlib.Path(__file__).resolve().parents[3]


def test_readme_mcp_command_brings_up_the_foo_system(ros_domain: int, tmp_path) -> None:
    block = re.search(r'```bash\n(.*?)```', section('The MCP (`wurde_mcp`)'), re.S).group(1)
    lines = [line for line in block.strip().splitlines() if line.strip()]
    assert lines[0] == 'source env.sh'
    # Run the page's lines; exec the last so that stopping the shell stops the MCP itself.
    script = '\n'.join(lines[:-1] + ['exec ' + lines[-1]])
    env = dict(os.environ, WURDE_LOG_DIRECTORY=str(tmp_path))
    table = Table()
    try:
        with ChildProcess(['bash', '-c', script], env=env, python=False, cwd=ROOT) as mcp:
            mcp.expect('MCP ready', timeout=60)
            rows = table.until(lambda r: r.get('FooServer', {}).get('status') == StatusMode.ACTIVE
                               and r.get('FooClient', {}).get('status') == StatusMode.ACTIVE,
                               'FooServer and FooClient active')
            assert set(rows) == {'FooServer', 'FooClient'}
            log = tmp_path / 'mcp-modules' / 'FooClient.log'
            deadline = time.monotonic() + 60
            while not ('Info: MaxRange 8.0' in log.read_text() and 'Val ' in log.read_text()):
                assert time.monotonic() < deadline, f'FooClient printed no info and data:\n{log.read_text()}'
                table.manager.wait(0.1)
            assert mcp.stop() == 0
    finally:
        table.close()
    client_log = (tmp_path / 'mcp-modules' / 'FooClient.log').read_text()
    assert 'Info: MaxRange 8.0' in client_log and 'Val ' in client_log
