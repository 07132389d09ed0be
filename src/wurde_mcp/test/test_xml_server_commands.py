"""The xmlServer's AURS commands beyond var/push/help, over real sockets: the pose commands and their
pushes (the seed's ``cmd="odopose pose"``), the server core's module/alive/ping/shelp, the laser
commands and the var options type=, call=, returnType=, log, isLogging, copy, dest= and desc."""

from __future__ import annotations

import pathlib
import time

import pytest
from xml_server_fixture import DEADLINE, Raw, Start, make_pool

from wurde_mcp.xml_server import Variable, VariablePool
from wurde_mcp.xml_server.utm import to_utm
from wurde_mcp.xml_server.var_call import parse_call

POSE_BLOCK = ['<odoPose name="poses">',
              '<pose name="newest" x="1.531" y="-21.912" h="-2.026" tod="1286376207.875200" '
              'vel="0.000" q="0"/>',
              '</odoPose>']


def _gps_pool() -> VariablePool:
    pool = make_pool()
    pool.add(Variable('gps.fix', 'd', '(r) lat lon alt sats quality hdop', [
        -33.8568, 151.2153, 10.0, 9.0, 2.0, 0.8]))
    pool.add(Variable('utmPose.pose', 'pose', '(r) local grid', [1.0, 2.0, float('nan'), 1.5e9]))
    return pool


# ---- poses --------------------------------------------------------------------------------------

def test_odopose_pose_answers_as_aurs(start: Start) -> None:
    raw = Raw(start().port)
    raw.send('<odoPose pose/>\n')
    assert raw.until(lambda line: line == '</odoPose>') == POSE_BLOCK
    raw.send('odopose pose\n')                           # the seed's lazy form: the client's tag
    assert raw.until(lambda line: line == '</odopose>')[0] == '<odopose name="poses">'
    assert raw.ask('odoPose') == '<odoPose info="done"/>'
    assert raw.ask('odoPose poseAtTime=2 pose') == '<odoPose warning="Unknown option: poseAtTime"/>'
    assert raw.ask('mapPose pose') == \
        '<mapPose warning="No resources, missing mapPose (no pose in mapPose.pose yet)"/>'
    assert raw.ask('utmPose pose') == \
        '<utmPose warning="No resources, missing utmPose (no GPS fix yet (gps.fix))"/>'


def test_utmpose_is_utm_from_the_gps_fix(start: Start) -> None:
    raw = Raw(start(pool=_gps_pool()).port)
    raw.send('utmPose pose\n')
    lines = raw.until(lambda line: line == '</utmPose>')
    # Sydney Opera House: 56H 334900.57 E 6252288.75 N (south: northing + 10 000 km)
    assert lines[1] == ('<pose name="newest" x="334900.570" y="6252288.753" h="nan" '
                        'tod="1500000000.000000" vel="0.000" q="2"/>')
    point = to_utm(55.7858, 12.5218)                  # and the north: DTU, zone 33
    assert (point.zone_name, round(point.easting), round(point.northing)) == \
        ('33N', 344604, 6185020)


def test_the_seeds_time_push_runs_odopose_pose(start: Start) -> None:
    raw = Raw(start().port)
    assert raw.ask('<push t=0.05 cmd="odopose pose"/>').startswith('<push info="added push 1"')
    lines = raw.until(lambda line: line == '</odopose>')
    assert lines[-3:] == [line.replace('odoPose', 'odopose') for line in POSE_BLOCK]


def test_odoposepush_runs_on_pose_updates(start: Start) -> None:
    pool = make_pool()
    raw = Raw(start(pool=pool).port)
    assert raw.ask('odoPosePush cmd="odoPose pose"') == \
        '<odoPosePush info="push command succeded - now 1 cmds and 0 calls" number="1"/>'
    pool.update('odoPose.pose', [4.0, 5.0, 0.5, 1286376300.25])
    lines = raw.until(lambda line: line == '</odoPose>')
    assert lines[-2] == ('<pose name="newest" x="4.000" y="5.000" h="0.500" '
                         'tod="1286376300.250000" vel="0.000" q="0"/>')
    raw.send('odoPosePush list\n')
    listing = raw.until_done()
    assert listing[0] == '<help subject="Push command list">' and 'cmd="odoPose pose"' in listing[1]
    assert raw.ask('odoPosePush cmd="odoPosePush list"').startswith(
        '<odoPosePush warning="push command failed: a push cannot run odoPosePush')
    assert raw.ask('odoPosePush flush') == \
        '<odoPosePush info="push command succeded - now 0 cmds and 0 calls"/>'
    assert raw.ask('utmPosePush cmd="utmPose pose"') == \
        '<utmPosePush warning="No interface resource (no gps in this server)"/>'


# ---- the server core ----------------------------------------------------------------------------

def test_alive_ping_and_shelp(start: Start) -> None:
    raw = Raw(start().port)
    last = raw.ask('alive')
    assert last.startswith('<alive last="') and 0.0 <= float(last.split('"')[1]) < DEADLINE
    before = time.time()
    reply = raw.ask(f'<ping tod="{before - 2.0:.6f}"/>')
    tod, delay = float(reply.split('tod="')[1].split('"')[0]), \
        float(reply.split('clientToServerSec="')[1].split('"')[0])
    assert before <= tod <= time.time() and 2.0 <= delay < 2.0 + DEADLINE
    assert raw.ask('ping').startswith('<ping tod="')
    assert raw.ask('ping tod=soon') == '<ping warning="tod=&quot;soon&quot; is not sss.usec"/>'
    raw.send('shelp\n')
    assert raw.until(lambda line: 'info="done"' in line)[:2] == \
        ['<help subject="server help">', '----- Main help:']


def test_module_list_load_and_unload(start: Start) -> None:
    raw = Raw(start().port)
    raw.send('module list\n')
    lines = raw.until_done()
    assert lines[:3] == ['<help subject="module list">', "Module core 'xmlServer-1.0'",
                         '      Handles: push q help quit exit shelp module alive ping']
    assert 'Module 6 laser a if (server interface client)' in lines
    assert raw.ask('module load=odoPose') == '<module info="done"/>'
    assert raw.ask('module load=auavoid.so').startswith(
        '<module warning="Module load error: auavoid.so: this server loads no plug-ins')
    assert raw.ask('module load=if alias=cam') == '<module info="done"/>'
    assert raw.ask('module load=if alias=cam') == \
        '<module warning="alias=cam: a command of that name exists"/>'
    assert raw.ask('cam var list') == \
        '<cam warning="No connection to server - not send: var list\\n"/>'
    assert raw.ask('module fly=high') == '<module warning="unused options  fly=&apos;high&apos;"/>'
    assert raw.ask('module unload=cam') == '<module info="done"/>'
    assert raw.ask('cam var list') == '<cam warning="Unsupported function keyword"/>'
    assert raw.ask('module unload=var').startswith('<module warning="Unload failed')
    raw.send('module\n')
    assert raw.until_done()[0] == '<help subject="module help">'


def test_a_bad_connect_is_refused_and_a_dead_port_is_retried(start: Start) -> None:
    raw = Raw(start().port)
    for bad in ('connect=nowhere', 'connect=example.org:24920', 'connect=127.0.0.1:99999',
                'connect'):
        assert raw.ask(f'laser {bad}').startswith('<laser warning="connect'), bad
    assert raw.ask('laser connect=127.0.0.1:1') == \
        '<laser info="connection requested to 127.0.0.1:1"/>'
    raw.send('laser status\n')
    assert 'This interface is connected (false) to 127.0.0.1 1' in raw.until_done()
    assert raw.ask('laser hup') == '<laser info="HUP (hangup) requested"/>'
    assert raw.ask('laser trap cmd="x"') == \
        '<laser warning="trap is not supported by this server&apos;s if module"/>'


# ---- laser --------------------------------------------------------------------------------------

def test_laserdata_and_laserobst(start: Start) -> None:
    pool = make_pool()
    raw = Raw(start(pool=pool).port)
    assert raw.ask('laserdata') == \
        '<laserdata warning="No resources, missing laser scan (no scan in laser.ranges yet)"/>'
    pool.update('laser.ranges', [1.0, 2.5, 3.25])
    assert raw.ask('laserdata') == \
        '<laserdata name="scan" serial="1" count="3" unit="m" ranges="1 2.5 3.25"/>'
    assert raw.ask('laserdata scanget') == '<laserdata warning="Unknown option: scanget"/>'
    assert raw.ask('laserobst').startswith('<laserobst warning="No obstacle resource')


# ---- var options --------------------------------------------------------------------------------

def test_var_type_makes_a_new_variable_but_not_in_the_robots_structures(start: Start) -> None:
    raw = Raw(start().port)
    assert raw.ask('<var goal.pose="1 2 0.5" type=pose/>') == \
        ('<var name="goal.pose" typ="pose" size="3" value="1 2 0.5" x="1" y="2" th="0.5" '
         'oldValue="(null)"/>')
    assert raw.ask('var goal.pose="3 4 0"') == \
        '<var name="goal.pose" typ="pose" size="3" value="3 4 0" x="3" y="4" th="0" oldValue="1 2 0.5"/>'
    assert raw.ask('var note="hello" type=s') == \
        '<var name="note" typ="s" size="5" value="hello" oldValue="(null)"/>'
    assert raw.ask('var drive.speedo="1"') == \
        '<var warning="not found - try: var help" name="drive.speedo"/>'
    assert raw.ask('var n="1" type=quaternion').startswith(
        '<var warning="type=quaternion is not one of')
    raw.send('var goal\n')
    assert raw.until_done()[:3] == ['<help subject="var list" name="goal">',
                                    'Description:                  new', '  pose=3 4 0']


@pytest.mark.parametrize('line, first', [
    ("var call='hypot(3, 4)'", '<var method="hypot" par="dd" found="true" value="5" structCnt="0">'),
    ("var call='atan2(1,1)'", '<var method="atan2" par="dd" found="true" value="0.785398" '
                              'structCnt="0">'),
    ("var call='hypot(3000, 4000)'", '<var method="hypot" par="dd" found="true" value="5000.0000" '
                                     'structCnt="0">'),
    ("var call='gmk(\"x\", 2)'", '<var method="gmk" par="sd" found="false" value="0" '
                                 'structCnt="0">'),
])
def test_var_call_answers_as_aurs(start: Start, line: str, first: str) -> None:
    raw = Raw(start().port)
    raw.send(line + '\n')
    assert raw.until(lambda got: got == '</var>') == [first, '</var>']


def test_var_call_errors_and_return_type(start: Start) -> None:
    raw = Raw(start().port)
    assert raw.ask("var call='hypot'") == \
        '<var warning="method parsing error - must have prackets"/>'
    assert raw.ask("var call='hypot(3,,4)'") == '<var warning="method parameter parsing error"/>'
    raw.send("var call='pi()' returnType=octopus\n")
    assert raw.until(lambda got: got == '</var>')[1] == \
        'Specified struct type octopus is not supported - (OK if resource owns returned structures)'
    assert parse_call("me(1, 'a', -2.5e1)") == ('me', 'dsd', [1.0, 'a', -25.0])


def test_var_log_writes_a_logged_structure_on_its_updates(start: Start,
                                                          tmp_path: pathlib.Path) -> None:
    pool = make_pool()
    raw = Raw(start(pool=pool, data_path=str(tmp_path)).port)
    path = tmp_path / 'xmlServer.var.log'
    assert raw.ask('var isLogging odoPose') == '<var info="Struct odoPose is logged false"/>'
    assert raw.ask('var log odoPose') == \
        f'<var info="Struct odoPose is logged (true) to {path}, file open (true)"/>'
    assert raw.ask('var isLogging odoPose.pose') == \
        '<var info="Variable odoPose.pose is logged true"/>'
    raw.send('var odoPose\n')
    assert ' Lpose=1.531 -21.912 -2.026 1286376207.8752' in raw.until_done()
    pool.update('odoPose.pose', [7.0, 8.0, 0.25, 1286376300.0])
    deadline = time.monotonic() + DEADLINE
    while 'odoPose.pose 7 8 0.25 1286376300' not in path.read_text():
        assert time.monotonic() < deadline, path.read_text()
        raw.ask('alive')                                 # a turn of the server
    assert raw.ask('var log=false odoPose').startswith('<var info="Struct odoPose is logged (false)')
    assert raw.ask('var log=false') == '<var info="done"/>'
    assert raw.ask('var log') == f'<var info="Opened logfile (true) as {path}"/>'
    assert raw.ask('var log nothere') == '<var warning="not found - try: var help" name="nothere"/>'


def test_a_logfile_that_cannot_be_opened_is_refused(start: Start, tmp_path: pathlib.Path) -> None:
    raw = Raw(start(data_path=str(tmp_path / 'missing')).port)
    assert raw.ask('var log').startswith('<var warning="cannot open logfile ')


def test_var_copy_has_dest_and_desc(start: Start) -> None:
    raw = Raw(start().port)
    raw.send('var camPool.device0 copy dest=. desc\n')
    assert raw.until_done() == [
        '<var name="camPool.device0.intrinsic" typ="m2" size="9" value="709 0 320; 0 709 240; '
        '0 0 1" dest="." desc="(r/w) intrinsic matrix"/>',
        '<var name="camPool.device0.name" typ="s" size="17" value="Logitech Pro 3000" dest="." '
        'desc="(r) camera name"/>',
        '<var info="done"/>']


@pytest.mark.parametrize('line', [
    'odoPose pose=1', 'odoPosePush', 'odoPosePush i=0 cmd="odoPose pose"', 'odoPosePush cmd="<x"',
    'ping tod=1e400', 'ping tod=nan', 'module list=1 reslist', 'module load=', 'module load=if alias=a.b',
    'module load=if alias=var', 'module unload=', 'laser connect=[::1]:x', 'laser cmd=""',
    'laserOnConnect', 'laserOnConnect cmd=""', "var call='sqrt(-1)'", "var call='exp(1e9)'",
    "var call='floor(1e400)'", "var call='x(\"a)'", 'var call=', 'var x..y="1"',
    'var .x="1"', 'var x="1" type=', 'var isLogging', 'var log=maybe nothere', 'var dest=. copy',
    'var copy', 'laserdata 1', 'shelp shelp', 'utmPose pose',
])
def test_malformed_new_commands_are_answered_not_crashed(start: Start, line: str,
                                                         tmp_path: pathlib.Path) -> None:
    raw = Raw(start(pool=_gps_pool(), data_path=str(tmp_path)).port)
    raw.send(line + '\n')
    raw.send('alive\n')
    lines = raw.until(lambda got: got.startswith('<alive last='))
    assert len(lines) >= 2, lines                     # the command was answered, then alive
    assert not [got for got in lines if 'failed: ' in got and 'error=' in got], lines
