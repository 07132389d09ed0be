"""eye under the MCP: its images come from the stream the MCP assigns to ``EyeImageClient``
(STRAT_ASSIGNED, the guide's appendix mapping), here the pattern camera's ``Camera``."""

from __future__ import annotations

import os
import pathlib

from eye_fixture import pattern_camera, status
from screens import xvfb
from sim_fixture import Observer
from wurde_testing import ChildProcess, find_executable

CONFIG = """<?xml version="1.0" encoding="UTF-8"?>
<mcp-config>
  <module name="Eye" managed="managed">
    <binary>wurde_drivers/eye</binary>
    <options>-d window</options>
  </module>
</mcp-config>
"""
MAPPINGS = """<?xml version="1.0" encoding="UTF-8"?>
<mcp-mappings>
  <connect module="Eye">
    <input interface="ImageTransport" source="Camera" object="EyeImageClient"/>
  </connect>
</mcp-mappings>
"""


def test_the_mcp_assigns_the_eyes_stream(ros_domain: int, tmp_path: pathlib.Path) -> None:
    (tmp_path / 'mcp-config.xml').write_text(CONFIG)
    (tmp_path / 'mcp-mappings.xml').write_text(MAPPINGS)
    observer = Observer({'Eye': 'ImageDisplay'})
    try:
        with xvfb(tmp_path) as (display, _), pattern_camera('Camera', 'rgb8'):
            env = dict(os.environ, DISPLAY=display, WURDE_LOG_DIRECTORY=str(tmp_path))
            with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-a',
                               '-c', str(tmp_path / 'mcp-config.xml'),
                               '-m', str(tmp_path / 'mcp-mappings.xml')], env=env) as mcp:
                mcp.expect('MCP ready', timeout=60)
                observer.until(lambda o: 'Eye' in o.infos and o.infos['Eye'].stream == 'Camera'
                               and (s := status(o)) is not None and s.frames_shown >= 1,
                               'the assigned stream shown', timeout=30)
                assert observer.infos['Eye'].title == 'Eye: Camera'           # the default follows
                mcp.stop(timeout=30)
    finally:
        observer.close()
    log = (tmp_path / 'mcp-modules' / 'Eye.log').read_text()
    assert log.rstrip().endswith('--- exit code 0'), log[-4000:]
