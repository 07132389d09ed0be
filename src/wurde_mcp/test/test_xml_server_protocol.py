"""The xmlServer speaks the seed's protocol (AU Robot Servers, "Interface description" to "Online
help"): greeting, var get/set/list/allcopy/help, unsupported keywords, help, push and varpush, the
end of a session, the lazy and typographic forms; and the command tokenizer's properties."""

from __future__ import annotations

import time
from collections.abc import Iterator

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from xml_server_fixture import (DEADLINE, POSE_LINE, RANGES_LINE, Raw, Start, make_pool,
                                wait_until)

from wurde_mcp.xml_server import (Command, CommandError, ServerSettings, Session, VarError,
                                  XmlClient, XmlServer)
from wurde_mcp.xml_server.command import escape, parse_command, reply
from wurde_mcp.xml_server.push import EventPush, TimePush


@pytest.fixture
def client(start: Start) -> Iterator[Raw]:
    """A raw client of a server with the test pool, its greeting read."""
    raw = Raw(start().port)
    yield raw
    raw.close()


# ---- command.py ---------------------------------------------------------------------------------

NAMES = st.from_regex(r'[A-Za-z0-9_.:\-]{1,12}', fullmatch=True)
VALUES = st.none() | st.text(st.characters(blacklist_categories=('Cs', 'Cc')) | st.just('\t'),
                             max_size=40)


@settings(max_examples=300, deadline=None)
@given(NAMES, st.lists(st.tuples(NAMES, VALUES), max_size=6))
def test_a_reply_parses_back_to_its_attributes(tag: str,
                                               attrs: list[tuple[str, str | None]]) -> None:
    assert parse_command(reply(tag, attrs)) == Command(tag, attrs, 'command')


@settings(max_examples=500, deadline=None)
@given(st.text(max_size=80) | st.binary(max_size=80).map(lambda b: b.decode('utf-8', 'replace')))
def test_any_line_parses_or_raises_command_error(line: str) -> None:
    assert _parses_or_says_why(line) in KINDS


def _parses_or_says_why(line: str) -> str:
    """What a line is: the kind of the command it parses to (it has a tag), or ``'refused'`` when
    it raises a CommandError with a reason; any other exception propagates."""
    try:
        command = parse_command(line)
    except CommandError as exc:
        return 'refused' if str(exc) else 'refused without a reason'
    return command.kind if command.tag else 'a command without a tag'


KINDS = ('command', 'opening', 'closing', 'declaration', 'refused')


@settings(max_examples=200, deadline=None)
@given(st.lists(st.sampled_from(['<', '>', '/', '?', '=', '"', "'", '\u201d', ' ', 'a', 'var',
                                 '&lt;', '&', '\t', '.']), max_size=20))
def test_tag_like_noise_parses_or_raises_command_error(parts: list[str]) -> None:
    assert _parses_or_says_why(''.join(parts)) in KINDS


@pytest.mark.parametrize('line, tag, args, kind', [
    ('<var mappose.pose=\u201d\u201d/>', 'var', [('mappose.pose', '')], 'command'),
    ('<var mappose.pose=""/>\n', 'var', [('mappose.pose', '')], 'command'),
    ("<var a='x y'/>", 'var', [('a', 'x y')], 'command'),
    ('<push t=1.5 cmd="var odopose.pose"/>', 'push', [('t', '1.5'), ('cmd', 'var odopose.pose')],
     'command'),
    ('<varpush struct=odoPose i=3/>', 'varpush', [('struct', 'odoPose'), ('i', '3')], 'command'),
    ('<module list/>', 'module', [('list', None)], 'command'),
    ('var odopose.pose c.d', 'var', [('odopose.pose', None), ('c.d', None)], 'command'),
    ('push t=1 cmd="var x"', 'push', [('t', '1'), ('cmd', 'var x')], 'command'),
    ('  q \r\n', 'q', [], 'command'),
    ('<var a="&lt;&gt;&amp;&quot;&apos;&#65;&nbsp;"/>', 'var', [('a', '<>&"\'&#65;&nbsp;')],
     'command'),
    ('<?xml version="1.0" encoding="UTF-8"?>', 'xml', [('version', '1.0'), ('encoding', 'UTF-8')],
     'declaration'),
    ('<marg name="paroll client" version="1267">', 'marg',
     [('name', 'paroll client'), ('version', '1267')], 'opening'),
    ('</marg>', 'marg', [], 'closing'),
])
def test_the_seed_forms_parse(line: str, tag: str, args: list[tuple[str, str | None]],
                              kind: str) -> None:
    command = parse_command(line)
    assert (command.tag, command.args, command.kind) == (tag, args, kind)
    assert command.is_closing == (kind == 'closing')
    assert command.is_opening == (kind in ('opening', 'declaration'))


@pytest.mark.parametrize('line, reason', [
    ('<var a="x/>', 'unterminated quote'),
    ('<', "no tag name after '<'"),
    ('<>', "no tag name after '<'"),
    ('< var/>', "no tag name after '<'"),
    ('<var a=1', "no '>'"),
    ('var \x01x', 'control character 0x01'),
    ('', 'empty'),
    ('"x"', 'no command keyword'),
    ('<var a=b"c/>', 'unexpected'),
    ('<a/><b/>', 'unexpected'),
])
def test_malformed_lines_raise_with_a_reason(line: str, reason: str) -> None:
    with pytest.raises(CommandError, match=reason):
        parse_command(line)


def test_reply_escapes_its_values_onto_one_line() -> None:
    assert reply('var', [('a', 'x"<>&\'\n'), ('list', None)]) == \
        '<var a="x&quot;&lt;&gt;&amp;&apos;&#xa;" list/>\n'
    with pytest.raises(ValueError):
        reply('var', [('a b', 'x')])


# ---- push schedules -----------------------------------------------------------------------------

def test_a_time_push_keeps_its_phase_and_skips_missed_periods() -> None:
    pool = make_pool()
    push = TimePush(1, 'var x', parse_command('var x'), period=0.5, start=100.0)
    fired = [now for now in (100.2, 100.5, 100.7, 101.04, 101.49, 101.5, 103.1, 103.2, 103.5)
             if push.poll(now, pool)]
    # due at 100.5, 101.0 (late: 101.04), 101.5; 102.0..103.0 missed in a stall: one run at 103.1
    assert fired == [100.5, 101.04, 101.5, 103.1, 103.5]
    assert push.count == 5 and push.next_due == 104.0


def test_an_update_push_runs_on_every_ith_update() -> None:
    pool = make_pool()
    push = EventPush(1, 'var x', parse_command('var x'), 'odoPose', 3, pool.updates('odoPose'))
    runs = 0
    for k in range(10):
        pool.update('odoPose.pose', [k, 0, 0])
        due = push.pending(pool)                # what lets serve() skip its wait
        assert push.poll(0.0, pool) == due
        runs += due
    assert runs == 3
    for _ in range(7):                  # 7 updates in one turn: one run, the phase kept
        pool.update('odoPose.pose', [0, 0, 0])
    assert push.poll(0.0, pool) and not push.poll(0.0, pool)
    pool.update('odoPose.pose', [0, 0, 0])
    assert push.poll(0.0, pool)         # 10 + 7 + 1 = 18 updates: the 6th run


# ---- settings -----------------------------------------------------------------------------------

@pytest.mark.parametrize('port', [0, 24919, 24930])
def test_ports_of_the_seed_or_any(port: int) -> None:
    assert ServerSettings(port=port).port == port


@pytest.mark.parametrize('change', [{'port': 24918}, {'port': 24931}, {'port': 80},
                                    {'max_clients': 0}, {'idle_timeout': 0}, {'name': 'x y'}])
def test_bad_settings_are_refused(change: dict[str, object]) -> None:
    with pytest.raises(ValueError):
        ServerSettings(**change)        # type: ignore[arg-type]


# ---- the server ---------------------------------------------------------------------------------

def test_greeting_and_the_clients_opening_are_silent(start: Start) -> None:
    server = start(name='xmlServer')
    raw = Raw(server.port)
    assert raw.greeting == ['<?xml version="1.0" encoding="UTF-8"?>',
                            '<xmlServer name="xmlServer" version="1.0">']
    raw.send('<?xml version="1.0" encoding="UTF-8"?>\n<marg name="paroll client" version="1267">\n')
    assert raw.ask('<var odoPose.pose=""/>') == POSE_LINE
    raw.close()


def test_var_get_as_in_the_seed(client: Raw) -> None:
    assert client.ask('<var odopose.pose=""/>') == POSE_LINE
    assert client.ask('<var odoPose.poser=""/>') == \
        '<var warning="not found - try: var help" name="odoPose.poser"/>'
    assert client.ask('<var laser.ranges=""/>') == \
        RANGES_LINE
    assert client.ask('<var camPool.device0.name=""/>') == \
        '<var name="camPool.device0.name" typ="s" size="17" value="Logitech Pro 3000"/>'


def test_lazy_forms_quotes_and_any_case(client: Raw) -> None:
    for line in ('var odopose.pose', '<var mappose.pose=\u201d\u201d odopose.pose=\u201d\u201d/>',
                 "<var odoPose.pose=''/>", '   var   ODOPOSE.POSE   '):
        client.send(line + '\n')
        assert POSE_LINE in client.until(lambda got: got == POSE_LINE or 'done' in got), line
        if 'mappose' in line:
            assert client.line() == '<var info="done"/>'
    assert client.ask('<VAR ODOPOSE.POSE=""/>') == POSE_LINE.replace('<var ', '<VAR ')


def test_var_set_answers_the_new_and_old_value(client: Raw) -> None:
    assert client.ask('<var drive.speed="0.5"/>') == \
        '<var name="drive.speed" typ="d" size="1" value="0.5" oldValue="0"/>'
    assert client.ask('<var DRIVE.SPEED="0.25"/>') == \
        '<var name="drive.speed" typ="d" size="1" value="0.25" oldValue="0.5"/>'
    assert client.ask('<var camPool.device0.intrinsic="1 0; 0 1"/>') == \
        ('<var name="camPool.device0.intrinsic" typ="m2" size="4" value="1 0; 0 1" '
         'oldValue="709 0 320; 0 709 240; 0 0 1"/>')


@pytest.mark.parametrize('line, warning', [
    ('<var drive.speed="-1"/>', 'refused: a negative speed'),
    ('<var laser.ranges="1 2"/>', 'laser.ranges is read-only'),
    ('<var drive.speed="fast"/>', '"fast" is not a value of type d'),
    ('<var drive.speedo="1"/>', 'not found - try: var help'),
])
def test_a_refused_set_warns_and_keeps_the_value(client: Raw, line: str, warning: str) -> None:
    assert client.ask(line).startswith(f'<var warning="{escape(warning)}" name="')
    assert client.ask('var drive.speed') == '<var name="drive.speed" typ="d" size="1" value="0"/>'


def test_multi_get_answers_each_then_done(client: Raw) -> None:
    assert client.ask('<var odoPose.pose="" laser.ranges="" nothere=""/>') == POSE_LINE
    assert client.until_done() == [
        RANGES_LINE,
        '<var warning="not found - try: var help" name="nothere"/>',
        '<var info="done"/>']


def test_var_list_lists_the_root(client: Raw) -> None:
    client.send('var list\n')
    assert client.until_done() == [
        '<help subject="var list" name=".">',
        "  camPool='struct';", "  drive='struct';", "  laser='struct';", "  odoPose='struct';",
        '(H: has time series, L: is logged, R: replay)',
        '</help>',
        '<var info="done"/>']


def test_var_struct_lists_its_members_with_descriptions(client: Raw) -> None:
    client.send('<var odopose=""/>\n')
    assert client.until_done() == [
        '<help subject="var list" name="odoPose">',
        'Description:                  odometry of the base',
        '  pose=1.531 -21.912 -2.026 1286376207.8752',
        '(H: has time series, L: is logged, R: replay)', '</help>', '<var info="done"/>']
    client.send('var odoPose desc\n')
    lines = client.until_done()
    assert lines[2:5] == [         # 80 columns, continued from column 30
        '  pose=1.531 -21.912 -2.026 1286376207.8752 (r) odometry pose x, y [m], th [rad]',
        '                             and time [s] of the robot seen from where it',
        '                             started']
    client.send('var camPool desc\n')
    assert "  device0='struct';" in client.until_done()


@pytest.mark.parametrize('line', ['<var campool.device0.allcopy=""/>',
                                  'var camPool.device0 allcopy', 'var CAMPOOL.DEVICE0.ALLCOPY',
                                  '<VAR camPool.device0 allCopy/>'])
def test_allcopy_sends_every_variable_of_the_structure(client: Raw, line: str) -> None:
    tag = line.lstrip('<').split()[0]
    client.send(line + '\n')
    assert client.until_done() == [
        f'<{tag} name="camPool.device0.intrinsic" typ="m2" size="9" '
        'value="709 0 320; 0 709 240; 0 0 1"/>',
        f'<{tag} name="camPool.device0.name" typ="s" size="17" value="Logitech Pro 3000"/>',
        f'<{tag} info="done"/>']


def test_var_help_is_the_seeds(client: Raw) -> None:
    client.send('<var help/>\n')
    lines = client.until_done()
    assert lines[:3] == ['<help subject="VAR">', '-------------------- Available VAR options:',
                         "'variable [variable]*'  Get value of variable(s)"]
    assert lines[-3:] == ['See also VARPUSH (update event handling)', '</help>',
                          '<var info="done"/>']
    assert '[struct.]allCopy        Get list of all variables for var pool copy' in lines
    for option in ("type=T                  semi-structure where T='pose' | '3d' | 'dq' | 's' | 't'",
                   "call='me(par1,par2,..)' Test a method call with name 'me' and some parameters",
                   'returnType=[lineseg|3d|pose|...] Expected struct result type of call',
                   'log[=false] struct      Start or stop logging of this struct',
                   'isLogging   struct      Is this structure beeing logged?'):
        assert option in lines


def test_an_unknown_keyword_is_answered_with_the_clients_tag(client: Raw) -> None:
    assert client.ask('<vur odopose.pose=""/>') == '<vur warning="Unsupported function keyword"/>'
    assert client.ask('VUR x') == '<VUR warning="Unsupported function keyword"/>'
    assert client.ask('var odopose.pose') == POSE_LINE


def test_help_has_the_seeds_structure(start: Start) -> None:
    def setup(server: XmlServer) -> None:
        server.add_command('camGet', lambda c, cmd: [], 'Get an image', group='cam')

    server = start(setup=setup)
    raw = Raw(server.port)
    raw.send('<help/>\n')
    lines = raw.until(lambda line: line.startswith('<help info='))
    assert lines[:3] == ['<help subject="server help">', '----- Main help:',
                         'This is xmlServer-1.0 a server in the AU Robot Server series']
    assert lines[3].startswith('running on host ') and lines[3].endswith(f' port {server.port}')
    groups = lines[lines.index('Available commands (from currently loaded modules):') + 1:
                   lines.index('All commands has a help option, e.g.:')]
    assert groups == ['- push q help quit exit shelp module alive ping', '- var varPush', '- pt',
                      '- odoPose odoPosePush', '- utmPose utmPosePush', '- mapPose mapPosePush',
                      '- laser laserOnConnect', '- laserdata laserobst', '- camGet']
    assert 'var help          Get, set and list variables' in lines
    assert 'pt help           Odometry pose from a robot controller: no reply' in lines
    assert 'q                 Close connection to this client by server' in lines
    assert 'var list' in lines
    assert lines[-2:] == ['</help>', '<help info="done"/>']


@pytest.mark.parametrize('line, subject, done', [
    ('<push help/>', 'PUSH', '<push info="done"/>'),
    ('varpush help', 'VARPUSH', '<varpush info="done"/>'),
    ('<q help/>', 'Q', '<q info="done"/>'),
    ('help var', 'VAR', '<help info="done"/>'),
])
def test_every_command_has_its_help(client: Raw, line: str, subject: str, done: str) -> None:
    client.send(line + '\n')
    lines = client.until_done()
    assert lines[0] == f'<help subject="{subject}">' and lines[-2:] == ['</help>', done]
    assert len(lines) > 3


def test_a_handler_that_fails_is_answered_and_the_session_goes_on(start: Start) -> None:
    def boom(client: Session, command: Command) -> list[str]:
        raise RuntimeError('no luck')

    server = start(setup=lambda s: s.add_command('boom', boom, 'Fails'))
    raw = Raw(server.port)
    assert raw.ask('boom') == '<boom error="boom failed: RuntimeError: no luck"/>'
    assert raw.ask('var odopose.pose') == POSE_LINE


@pytest.mark.parametrize('line', ['q', '<quit/>', 'EXIT', '</marg>'])
def test_q_and_the_closing_tag_end_the_session(start: Start, line: str) -> None:
    server = start()
    raw = Raw(server.port)
    raw.send(line + '\n')
    assert raw.to_eof() == ['</xmlServer>']
    wait_until(lambda: server.client_count == 0, 'the session to end')


def test_push_runs_every_t_seconds(client: Raw) -> None:
    sent = time.monotonic()
    assert client.ask('<push t=0.1 cmd="var odopose.pose"/>') == \
        '<push info="added push 1" number="1" t="0.1" cmd="var odopose.pose"/>'
    pushed = [client.line() for _ in range(5)]
    assert pushed == [POSE_LINE] * 5
    assert time.monotonic() - sent >= 5 * 0.1      # never faster than t
    client.send('push list\n')
    listed = [line for line in client.until_done() if line != POSE_LINE]
    assert len(listed) == 2 and listed[1] == '<push info="done"/>'
    assert listed[0].startswith('<push number="1" t="0.1" cmd="var odopose.pose" count="')
    client.send('push flush\n')
    lines = client.until(lambda line: line.startswith('<push info="flushed'))
    assert lines[-1] == '<push info="flushed 1 push" count="1"/>'
    assert set(lines[:-1]) <= {POSE_LINE}
    assert client.within(0.5) == []                # no more pushes after the flush


def test_varpush_runs_on_every_ith_update_of_the_structure(start: Start) -> None:
    pool = make_pool()
    server = start(pool=pool)
    raw = Raw(server.port)
    assert raw.ask('<varpush struct=odopose i=3 cmd="var odopose.pose"/>') == \
        '<varpush info="added push 1" number="1" struct="odoPose" i="3" cmd="var odopose.pose"/>'
    xs = []
    for k in range(1, 10):
        pool.update('odoPose.pose', [float(k), 0.0, 0.0])
        # two round trips: a push due to this update is sent by the end of the second one
        for sync in ('var laser.ranges', 'var drive.speed'):
            raw.send(sync + '\n')
            lines = raw.until(lambda line: sync.split()[1] in line)
            xs += [line.split('x="')[1].split('"')[0] for line in lines if 'odoPose' in line]
    assert xs == ['3', '6', '9']


@pytest.mark.parametrize('line, warning', [
    ('<push t=0.001 cmd="var odopose.pose"/>', 'not a period of at least 0.01 s'),
    ('<push t=abc cmd="var odopose.pose"/>', 't="abc" is not a number'),
    ('<push t=1/>', 'push needs t=seconds and cmd'),
    ('<push t=1 cmd="push t=1 cmd=q"/>', 'a push cannot run push'),
    ('<push t=1 cmd="vur x"/>', 'cmd vur: Unsupported function keyword'),
    ('<push t=1 cmd="var a=&quot;x"/>', 'bad cmd'),
    ('<varpush struct=nothere cmd="var x"/>', 'struct "nothere" not found'),
    ('<varpush struct=odoPose i=0 cmd="var x"/>', 'i=0 is not a count'),
])
def test_bad_pushes_are_refused(client: Raw, line: str, warning: str) -> None:
    answer = client.ask(line)
    assert answer.startswith(f'<{line[1:].split()[0]} warning="') and warning in answer.replace(
        '&quot;', '"')
    client.send('push list\n')
    assert client.until_done() == ['<push info="done"/>']


def test_pushes_are_limited_per_client(start: Start) -> None:
    raw = Raw(start(max_pushes=2).port)
    for number in (1, 2):
        assert f'added push {number}' in raw.ask('<push t=10 cmd="var odopose.pose"/>')
    assert 'too many pushes: 2 (max 2)' in raw.ask('<push t=10 cmd="var odopose.pose"/>')


def test_pushes_end_with_the_client(start: Start) -> None:
    sessions: list[Session] = []

    def me(client: Session, command: Command) -> list[str]:
        sessions.append(client)
        return [reply(command.tag, [('number', str(client.number))])]

    server = start(setup=lambda s: s.add_command('me', me, 'Who am I'))
    raw = Raw(server.port)
    assert raw.ask('me') == '<me number="1"/>'
    assert 'added push 1' in raw.ask('<push t=0.05 cmd="var odopose.pose"/>')
    assert raw.line() == POSE_LINE
    assert len(sessions[0].pushes) == 1
    raw.close()
    # The session stops counting as a client (and its pushes end) when it starts ending; it is
    # closed once its closing tag is sent, a moment later: wait for that, not for the count.
    wait_until(lambda: sessions[0].closed, 'the session to be closed')
    assert server.client_count == 0 and sessions[0].pushes == []
    other = Raw(server.port)
    assert other.within(0.3) == []                 # nobody else gets the pushes
    other.close()


# ---- the client ---------------------------------------------------------------------------------

def test_the_client_gets_sets_and_lists(start: Start) -> None:
    server = start()
    with XmlClient(port=server.port, timeout=DEADLINE) as robot:
        assert (robot.root, robot.server_name, robot.server_version) == \
            ('xmlServer', 'xmlServer', '1.0')
        pose = robot.get('odoPose.pose')
        assert pose[''] == 'var' and (pose['x'], pose['y'], pose['th']) == \
            ('1.531', '-21.912', '-2.026')
        assert robot.set('drive.speed', 0.5)['oldValue'] == '0'
        assert robot.set('camPool.device0.intrinsic', [1, 2])['value'] == '1 2'
        with pytest.raises(VarError, match='negative'):
            robot.set('drive.speed', -1.0)
        with pytest.raises(VarError, match='not found'):
            robot.get('odoPose.poser')
        listing = robot.request('var odoPose')
        assert [item[''] for item in listing] == ['help', '', '', '', '/help', 'var']
        assert listing[-1] == {'': 'var', 'info': 'done'}
        several = robot.request('var odoPose.pose laser.ranges')
        assert [item.get('name') for item in several] == ['odoPose.pose', 'laser.ranges', None]
        assert 'running on host' in robot.help() and 'allCopy' in robot.help('var')
        assert robot.request('vur') == [{'': 'vur', 'warning': 'Unsupported function keyword'}]
        assert robot.request('q help')[0] == {'': 'help', 'subject': 'Q'}
        assert robot.request('push t=0.05 cmd="var odoPose.pose"')[0]['info'] == 'added push 1'
        pushed = next(line for line in robot.lines(timeout=DEADLINE) if 'x' in line)
        assert pushed['name'] == 'odoPose.pose' and pushed['x'] == '1.531'
    wait_until(lambda: server.client_count == 0, 'the client to leave')
