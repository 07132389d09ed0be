"""The xml_server executable on real streams: this test supplies the localModule's Dead-Reckoning
stream and a chain link's command stream (with a Writable lock), a client reads odoPose.pose over
TCP, writes drive.command through the stream's request channel (the lock refuses the locked
member), and an event push (varpush) follows the stream's updates."""

from __future__ import annotations

import pathlib
import re
import time
from collections.abc import Callable

from wurde_core import CommsManager, LockMode, Pose3D, ProcessLocale, ProcessType, RunState, StatusMode
from wurde_core.interfaces import ActuatorState, LocalizationPose, SimpleControl
from wurde_mcp.xml_server import VarError, XmlClient
from wurde_testing import ChildProcess, find_executable
from wurde_testing import manual
from wurde_testing.sockets import LOOPBACK, listening_addresses

DEADLINE = 30.0


class Robot:
    """The test's module: supplies Localization/Dead-Reckoning and drive/command."""

    def __init__(self) -> None:
        self.manager = CommsManager('XmlTester')
        self.manager.set_no_sleep()
        self.pose = LocalizationPose('Localization/Dead-Reckoning')
        self.map_pose = LocalizationPose('Localization/Pose')
        self.drive = ActuatorState('drive/command')
        self.table = SimpleControl('mcp_control')             # as the MCP publishes its module table
        self.manager.register_supplier(self.table)
        self.manager.register_supplier(self.pose)
        self.manager.register_supplier(self.map_pose)
        self.manager.register_supplier(self.drive)
        self.drive.set_lock('force', LockMode.SUPPLIERS)
        self.requests: list[tuple[int, list[float], list[float]]] = []

    def publish(self, x: float, y: float, theta: float, stream: str = 'dr') -> None:
        obj = self.pose if stream == 'dr' else self.map_pose
        obj.data.pose = Pose3D(x, y, 0.0, theta, 0.0, 0.0)
        obj.publish_data()

    def publish_table(self) -> None:
        d = self.table.data
        d.module_names = ['PlutoBase', 'localModule']
        d.module_status = [StatusMode.ACTIVE, StatusMode.ACTIVE]
        d.module_managed = [ProcessType.CRITICAL, ProcessType.MANAGED]
        d.module_locale = [ProcessLocale.INTERNAL, ProcessLocale.INTERNAL]
        d.module_state = [RunState.RUN, RunState.IDLE]
        d.module_pid = [4242, 4343]
        d.module_host = ['localhost', 'localhost']
        d.module_heartbeat_age = [0.1, 0.2]
        d.module_restarts = [0, 2]
        self.table.publish_data()

    def pump(self) -> None:
        self.manager.step()
        while self.drive.get_next_request():
            r = self.drive.requests
            self.requests.append((int(r.cmd_flags.get_value()), list(r.position.get_value()),
                                  list(r.velocity.get_value())))

    def until(self, predicate: Callable[[], object], what: str, server: ChildProcess,
              every: Callable[[], object] = lambda: None) -> object:
        deadline = time.monotonic() + DEADLINE
        while True:
            self.pump()
            result = predicate()
            if result:
                return result
            assert server.process.poll() is None, f'{what}: xml_server exited: {server.stderr}'
            assert time.monotonic() < deadline, f'{what}: not within {DEADLINE} s; {server.stderr}'
            every()
            self.manager.wait(0.05)

    def close(self) -> None:
        self.manager.clean_up()


def _get(client: XmlClient, name: str) -> dict[str, str]:
    return client.get(name)


def _try_get(client: XmlClient, name: str) -> dict[str, str] | None:
    """The reply of a get, None while the variable does not exist."""
    try:
        return client.get(name)
    except VarError:
        return None


def _try_set(client: XmlClient, name: str, value: str) -> dict[str, str] | None:
    """The reply of a set the server took, None while it refuses it."""
    try:
        return client.set(name, value)
    except VarError:
        return None


def test_the_robot_streams_are_variables_and_commands_go_through_the_request_channel(ros_domain: int) -> None:
    robot = Robot()
    try:
        with ChildProcess([find_executable('wurde_mcp', 'xml_server'), '-p', '0']) as server:
            port = _port(server)
            assert listening_addresses(port) == [LOOPBACK], 'xml_server must bind 127.0.0.1 alone'
            with XmlClient(port=port, timeout=10.0) as client:
                assert client.server_name == 'xmlServer'
                # The pose as published, the stamp its fourth number (Mobotware's pose: x y th time).
                reply = robot.until(lambda: (r := _get(client, 'odopose.pose'))['x'] == '1.5' and r,
                                    'odoPose.pose read', server, every=lambda: robot.publish(1.5, -2.0, 0.25))
                assert reply['name'] == 'odoPose.pose' and reply['typ'] == 'pose' and reply['size'] == '4'
                assert (float(reply['y']), float(reply['th'])) == (-2.0, 0.25)
                assert float(reply['value'].split()[3]) > 0.0
                # Unknown names get the seed's warning.
                assert client.request('<var odoPose.poser=""/>')[0]['warning'] == 'not found - try: var help'

                # A command goes to drive/command's request channel once the server's writer is matched.
                taken = robot.until(lambda: _try_set(client, 'drive.command', '0 0 0 0.2 0.1'),
                                    'drive.command taken', server)
                assert taken['name'] == 'drive.command' and taken['value'].split()[0] == '0'
                robot.until(lambda: (0, [0.0, 0.0], [0.2, 0.1]) in [(f, p, [round(v, 3) for v in vel])
                                                                  for f, p, vel in robot.requests],
                            'the request arrived', server)
                # The supplier's lock on force refuses the member in the server, with the lock's reason.
                # (the lock reaches the server with the stream's info: wait for the refusal.)
                command = '<var drive.command="1 0 0 0.2 0.1 5"/>'
                refused = robot.until(lambda: 'force' in (r := client.request(command)[0]
                                                          ).get('warning', '') and r,
                                      'the locked member refused', server)
                assert 'lock' in refused['warning'], refused
                # Read-only variables refuse a write.
                assert 'read-only' in client.request('<var odoPose.pose="1 2 3"/>')[0]['warning']

                # An event push: every update of odoPose runs the command for this client.
                added = client.request('<varpush struct=odoPose i=1 cmd="var odoPose.pose"/>')[0]
                assert 'added' in added.get('info', ''), added
                pushed: list[dict[str, str]] = []

                def heard() -> bool:
                    pushed.extend(client.lines(timeout=0.05))
                    return any(p.get('x') == '4' for p in pushed)

                robot.until(heard, 'a pushed pose', server, every=lambda: robot.publish(4.0, 1.0, 0.0))
                assert all(p.get('name') == 'odoPose.pose' for p in pushed if p.get('') == 'var')

                # The MCP's module table: mcp.<module>.state|status|pid|restarts.
                state = robot.until(lambda: _try_get(client, 'mcp.localModule.state'), 'the module table', server,
                                    every=robot.publish_table)
                assert (state['typ'], state['value']) == ('s', 'IDLE')
                assert client.get('mcp.plutobase.pid')['value'] == '4242'
                assert client.get('mcp.localModule.restarts')['value'] == '2'
                assert client.get('mcp.PlutoBase.status')['value'] == 'ACTIVE'
            assert server.stop() == 0
    finally:
        robot.close()


def _port(server: ChildProcess) -> int:
    server.expect('xml_server listening on', timeout=60)
    return int(re.search(r'127\.0\.0\.1:(\d+)', server.stdout).group(1))


def test_the_readme_client_example_reads_the_pose_and_follows_pushes(ros_domain: int,
                                                                     tmp_path: pathlib.Path) -> None:
    code = manual.example('xml_client', 'python')
    script = tmp_path / 'xml_client.py'
    script.write_text(code)
    robot = Robot()
    try:
        with ChildProcess([find_executable('wurde_mcp', 'xml_server'), '-p', '0']) as server:
            port = _port(server)
            with XmlClient(port=port, timeout=10.0) as client:       # the server has both poses
                def both() -> bool:
                    robot.publish(1.5, -2.0, 0.25)
                    robot.publish(3.0, 4.0, 0.5, 'map')
                    return _get(client, 'odoPose.pose')['x'] == '1.5' and _get(client, 'mapPose.pose')['x'] == '3'
                robot.until(both, 'both poses in the server', server)
            with ChildProcess([str(script), str(port)]) as example:
                robot.until(lambda: example.process.poll() is not None, 'the example ended', server)
                assert example.stop() == 0, example.stderr          # (its output read to the end)
                lines = example.stdout.splitlines()
            assert lines[0] == 'odoPose 1.5 -2 0.25', lines
            assert len(lines) >= 2 and set(lines[1:]) == {"mapPose 3 4 0.5"}, lines
            assert server.stop() == 0
    finally:
        robot.close()
