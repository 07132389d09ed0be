"""Both of the guide's drive mappings reach one base (issue 10, section 3).

Chapter 1 (1.1.5) maps a SynchroDrive consumer to an ATRV Jr's ``HollowayRFlexDrive``; the
appendix (10.1) maps a RobotDrive consumer to a B21r's ``TomRFlexDrive``.  A base supplies its own
drive kind on ``<name>Drive`` and the other on the typed view ``<name>Drive/<Interface>``; the MCP
gives a mapping of that interface to ``<name>Drive`` the typed view.  The mappings below are the
guide's lines as printed.
"""

from __future__ import annotations

import os
import pathlib

import pytest
from sim_fixture import Observer, sim_config
from wurde_testing import ChildProcess, find_executable

CLIENT = '''#!/usr/bin/env python3
import sys
from wurde_core import CommsManager, ConnectionStrategy, RunState
from wurde_core.interfaces import {interface}
manager = CommsManager("{module}")
manager.parse_options(sys.argv)
manager.set_sleep(0.1)
drive = {interface}(ConnectionStrategy.ASSIGNED, "DriveClient")
manager.register_consumer(drive)
told = False
while manager.run_update() == RunState.RUN:
    if drive.is_connected() and not told:
        print("STREAM", drive.stream, flush=True)
        told = True
    if drive.is_connected() and drive.peers() > 0:
        drive.requests.{trans}.set_value(0.2)
        drive.publish_request()
manager.clean_up()
'''

CASES = {
    # guide 1.1.5: VectorMover's SynchroDrive DriveClient on the ATRV Jr HollowayRFlex
    'chapter1': ('ATRVJr', 'HollowayRFlex', 'VectorMover', 'SynchroDrive', 'trans',
                 '<input interface="SynchroDrive" source="HollowayRFlexDrive" object="DriveClient" />'),
    # guide 10.1: SynchroMover's RobotDrive DriveClient on the B21r TomRFlex
    'appendix': ('B21r', 'TomRFlex', 'SynchroMover', 'RobotDrive', 'trans_velocity',
                 '<input interface="RobotDrive" source="TomRFlexDrive" object="DriveClient" />'),
}


@pytest.mark.parametrize('case', sorted(CASES))
def test_a_guide_mapping_of_either_drive_interface_reaches_the_base(
        case: str, ros_domain: int, tmp_path: pathlib.Path) -> None:
    base_type, base, module, interface, trans, mapping = CASES[case]
    sim_config(tmp_path, elements={'base': {'type': base_type, 'name': base}})
    client = tmp_path / 'client.py'
    client.write_text(CLIENT.format(interface=interface, module=module, trans=trans))
    client.chmod(0o755)
    (tmp_path / 'mcp-config.xml').write_text(
        '<?xml version="1.0"?>\n<mcp-config>\n'
        f'<module name="{base}" managed="critical"><binary>wurde_drivers/dummy_base</binary>'
        f'<options>-n {base}</options></module>\n'
        f'<module name="{module}"><binary>{client}</binary></module>\n</mcp-config>\n')
    (tmp_path / 'mcp-mappings.xml').write_text(
        f'<?xml version="1.0"?>\n<mcp-mappings>\n<connect module="{module}">\n{mapping}\n'
        '</connect>\n</mcp-mappings>\n')
    env = dict(os.environ, WURDE_CONFIG_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path))
    observer = Observer({f'{base}Command': 'ActuatorState'})
    try:
        with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', str(tmp_path / 'mcp-config.xml'),
                           '-m', str(tmp_path / 'mcp-mappings.xml'), '-a'], env=env) as mcp:
            mcp.expect('MCP ready', timeout=90)
            observer.until(lambda o: any(round(m.velocity[0], 6) == 0.2
                                         for _, m in o.events[f'{base}Command']),
                           f'the {interface} client driving {base}', timeout=90)
            log = (tmp_path / 'mcp-modules' / f'{module}.log').read_text()
            native = 'SynchroDrive' if base_type == 'B21r' else 'RobotDrive'
            assert native != interface
            assert f'STREAM {base}Drive/{interface}' in log
    finally:
        observer.close()
