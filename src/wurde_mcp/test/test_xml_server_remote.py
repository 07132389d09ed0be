"""Two real ``xml_server`` processes on 127.0.0.1, the second a client of the first through
Mobotware's server-to-server commands (AU Robot Servers, "Get value to another server"):
``module load=if alias=cam``, ``cam connect=localhost:PORT``, ``cam varpush struct=odoPose
cmd="var odoPose copy"`` (copies into the structure ``var``), ``dest=`` and ``desc``, and
``camOnConnect``; the first server's odometry comes from this test's Dead-Reckoning stream.  Also
the manual's copy example (docs/mobotware.md), and ``utmPose``/``laserdata`` from GPS and laser streams."""

from __future__ import annotations

import pathlib

from test_xml_server_module import Robot, _port
from wurde_core.interfaces import GPS, RangeFinder
from wurde_testing import ChildProcess, find_executable
from wurde_testing import manual

from wurde_mcp.xml_server import VarError, XmlClient


def _get(client: XmlClient, name: str) -> dict[str, str] | None:
    try:
        return client.get(name)
    except VarError:
        return None


def _status(client: XmlClient) -> str:
    return '\n'.join(item.get('text', '') for item in client.request('cam status'))


def test_a_server_copies_another_servers_structure(ros_domain: int) -> None:
    robot = Robot()
    server = [find_executable('wurde_mcp', 'xml_server'), '-p', '0']
    try:
        with ChildProcess(server) as first, ChildProcess(server) as second:
            a_port, b_port = _port(first), _port(second)
            with XmlClient(port=a_port, timeout=10.0) as a, XmlClient(port=b_port, timeout=10.0) as b:
                # The first server's own pose commands, as AURS answers them.
                pose = robot.until(lambda: (r := a.request('odoPose pose'))[-1].get('') == '/odoPose'
                                   and r[1]['x'] == '1.500' and r,
                                   'odoPose pose', first, every=lambda: robot.publish(1.5, -2.0, 0.25))
                assert [item[''] for item in pose] == ['odoPose', 'pose', '/odoPose']
                assert (pose[1]['y'], pose[1]['h'], pose[1]['name']) == ('-2.000', '0.250', 'newest')
                assert a.request('utmPose pose')[0]['warning'].startswith('No resources, missing utmPose')

                assert b.request('module load=if alias=cam') == [{'': 'module', 'info': 'done'}]
                assert b.request(f'cam connect=localhost:{a_port}')[0]['info'] == \
                    f'connection requested to 127.0.0.1:{a_port}'
                robot.until(lambda: 'connected (true)' in _status(b), 'cam connected', second)
                sent = b.request('cam varpush struct=odoPose cmd="var odoPose copy"')[0]
                assert sent['info'] == 'send: varpush struct="odoPose" cmd="var odoPose copy"\\n'

                # Every update of odoPose on the first server lands in var.odoPose on the second.
                copied = robot.until(lambda: (r := _get(b, 'var.odoPose.pose')) and r['x'] == '3' and r,
                                     'the copy', second, every=lambda: robot.publish(3.0, 4.0, 0.5))
                assert (copied['typ'], copied['y'], copied['th']) == ('pose', '4', '0.5')
                listing = b.request('var var.odoPose desc')
                texts = [item.get('text', '') for item in listing]
                assert texts[1] == 'Description:                  new'
                assert texts[2].startswith('  pose=3 4 0.5 ') and texts[2].endswith(' added')

                # dest=. would put it over the second server's own odoPose.pose: refused.
                b.request('cam var odoPose copy dest=.')
                robot.until(lambda: 'odoPose.pose belongs to the robot' in _status(b),
                            'the refusal', second)
                # dest=pluto2. and desc: the first server's description comes with it.
                b.request('cam var odoPose copy dest=pluto2. desc')
                there = robot.until(lambda: _get(b, 'pluto2.odoPose.pose'), 'dest=pluto2.', second)
                assert there['x'] == '3'
                described = b.request('var pluto2.odoPose desc')
                assert any('dead-reckoning pose' in item.get('text', '') for item in described)

                # camOnConnect: sent again on every connection.
                assert 'now 1 pushCmds' in b.request(
                    'camOnConnect cmd="var odoPose copy dest=again."')[0]['info']
                assert b.request('cam hup')[0]['info'] == 'HUP (hangup) requested'
                assert 'connected (false)' in _status(b)
                assert b.request('cam connect')[0]['info'].startswith('connection requested')
                again = robot.until(lambda: _get(b, 'again.odoPose.pose'), 'the OnConnect copy', second)
                assert again['x'] == '3'
            assert first.stop() == 0 and second.stop() == 0
    finally:
        robot.close()


def test_the_readme_copy_example_copies_the_pose(ros_domain: int, tmp_path: pathlib.Path) -> None:
    code = manual.example('xml_copy', 'python')
    script = tmp_path / 'xml_copy.py'
    script.write_text(code)
    robot = Robot()
    server = [find_executable('wurde_mcp', 'xml_server'), '-p', '0']
    try:
        with ChildProcess(server) as first, ChildProcess(server) as second:
            ports = [str(_port(first)), str(_port(second))]
            with ChildProcess([str(script), *ports]) as example:
                robot.until(lambda: example.process.poll() is not None, 'the example ended', first,
                            every=lambda: robot.publish(2.5, -1.0, 0.75))
                assert example.stop() == 0, example.stderr
            assert example.stdout.splitlines() == ['copied 2.5 -1 0.75']
            assert first.stop() == 0 and second.stop() == 0
    finally:
        robot.close()


def test_utmpose_and_laserdata_come_from_the_gps_and_laser_streams(ros_domain: int) -> None:
    robot = Robot()
    gps, laser = GPS('PlutoGPS'), RangeFinder('PlutoLaser')
    robot.manager.register_supplier(gps)
    robot.manager.register_supplier(laser)

    def publish() -> None:
        gps.data.latitude, gps.data.longitude, gps.data.quality = -33.8568, 151.2153, 2
        gps.publish_data()
        laser.data.ranges = [1.0, 2.5, 8.0]
        laser.publish_data()

    try:
        with ChildProcess([find_executable('wurde_mcp', 'xml_server'), '-p', '0']) as server:
            with XmlClient(port=_port(server), timeout=10.0) as client:
                utm = robot.until(lambda: (r := client.request('utmPose pose'))[-1].get('') == '/utmPose'
                                  and r, 'utmPose pose', server, every=publish)
                assert (utm[1]['x'], utm[1]['y'], utm[1]['h'], utm[1]['q']) == \
                    ('334900.570', '6252288.753', 'nan', '2')
                scan = robot.until(lambda: 'ranges' in (r := client.request('laserdata')[0]) and r,
                                   'laserdata', server, every=publish)
                assert (scan['count'], scan['unit'], scan['ranges']) == ('3', 'm', '1 2.5 8')
            assert server.stop() == 0
    finally:
        robot.close()
