"""Run states across processes (guide 5.2.1): a module lives through Idle, Reset and Restart.

Events are ordered by their DDS source timestamps (the writer's clock when it wrote), so "nothing
was published while Idle" is checked exactly: no data event of the module was written between the
heartbeat description that said Idle and the one that said Run again.  No time window is guessed.
"""

from __future__ import annotations

import os
import signal
from typing import Any

import pytest

from conftest import HERE, Peer, until
from wurde_core import CommsManager, RunState
from wurde_core.interfaces import Foo, robot_object_class
from wurde_core.naming import topic
from wurde_core.qos import info_qos, stream_qos
from wurde_core.ros_adaptor import take_stamped


class Recorder:
    """Raw subscriptions on the test's node that keep every event with its source timestamp."""

    def __init__(self, manager: CommsManager) -> None:
        self.node = manager.node
        self.subscriptions: dict[str, Any] = {}
        self.events: dict[str, list[tuple[Any, int]]] = {}

    def add(self, key: str, msg_type: type, topic_name: str, qos: Any) -> None:
        self.subscriptions[key] = self.node.create_subscription(msg_type, topic_name,
                                                                lambda _m: None, qos)
        self.events[key] = []

    def take(self) -> None:
        for key, subscription in self.subscriptions.items():
            self.events[key].extend(take_stamped(subscription))


def _heartbeat(manager: CommsManager, module: str) -> Any:
    heartbeat = robot_object_class('Heartbeat')(f'heartbeat/{module}')
    heartbeat.set_queue_mode(True)
    manager.register_consumer(heartbeat)
    return heartbeat


def _command(manager: CommsManager, heartbeat: Any, state: RunState) -> None:
    until(manager, lambda: heartbeat.peers() > 0, what='heartbeat request matched')
    heartbeat.requests.state.set_value(state)
    heartbeat.publish_request()


def _state_stamp(recorder: Recorder, state: RunState, after: int = 0) -> int | None:
    for message, stamp in recorder.events['info']:
        if message.state.value == int(state) and stamp > after:
            return stamp
    return None


def test_idle_keeps_the_module_alive_and_silent_then_data_flows_again(manager, peer) -> None:
    worker = peer('Idler')
    worker.cmd('supply Foo idling queue')
    heartbeat = _heartbeat(manager, 'Idler')
    recorder = Recorder(manager)
    recorder.add('data', Foo.data_type, topic('idling', 'data'), stream_qos(True))
    recorder.add('info', heartbeat.info_type, topic('heartbeat/Idler', 'info'), info_qos(True))
    recorder.add('beats', heartbeat.data_type, topic('heartbeat/Idler', 'data'), stream_qos(True))
    worker.cmd('wait_subscribers idling')
    worker.cmd('stream idling')
    pid = worker.process.pid

    def data_count() -> int:
        recorder.take()
        return len(recorder.events['data'])

    until(manager, lambda: data_count() >= 5, what='data flowing')
    _command(manager, heartbeat, RunState.IDLE)
    worker.expect('STATE IDLE')

    def idle_beats() -> int:
        recorder.take()
        idle = _state_stamp(recorder, RunState.IDLE)
        return 0 if idle is None else sum(stamp > idle for _, stamp in recorder.events['beats'])

    # Heartbeats go on while Idle (the peer's TTL is 20 ms: a beat at least every 10 ms).
    until(manager, lambda: idle_beats() >= 3, what='heartbeats while idle')
    assert worker.process.poll() is None and worker.process.pid == pid
    _command(manager, heartbeat, RunState.RUN)
    worker.expect('STATE RUN')
    idle_at = _state_stamp(recorder, RunState.IDLE)
    assert idle_at is not None

    def resumed() -> bool:
        recorder.take()
        run_at = _state_stamp(recorder, RunState.RUN, after=idle_at)
        return run_at is not None and any(s > run_at for _, s in recorder.events['data'])

    until(manager, resumed, what='data after returning to Run')
    run_at = _state_stamp(recorder, RunState.RUN, after=idle_at)
    written_while_idle = [s for _, s in recorder.events['data'] if idle_at < s < run_at]
    assert written_while_idle == []
    # The loop body did not run in Idle: the loop numbers go on without a gap.
    loops = [int(message.ranges[0]) for message, _ in recorder.events['data']]
    assert loops == list(range(loops[0], loops[0] + len(loops)))
    assert worker.process.poll() is None and worker.process.pid == pid


def test_reset_by_default_forgets_unread_events_and_returns_to_run(
        manager: CommsManager, other: CommsManager) -> None:
    consumer = Foo('into_reset')
    consumer.set_queue_mode(True)
    manager.register_consumer(consumer)
    supplier = Foo('into_reset')
    supplier.set_queue_mode(True)
    other.register_supplier(supplier)
    heartbeat = robot_object_class('Heartbeat')('heartbeat/Tester')
    other.register_consumer(heartbeat)
    manager.step()
    assert supplier.wait_for_peers(20) and heartbeat.wait_for_peers(20)
    for value in range(3):
        supplier.data.ranges = [float(value)]
        supplier.publish_data()
    assert supplier.wait_delivered(20)
    manager.step()  # takes the three events in; the program has not read them
    assert consumer.new_data()
    heartbeat.requests.state.set_value(RunState.RESET)
    heartbeat.publish_request()
    assert heartbeat.wait_delivered(20)
    until(manager, lambda: manager.state == RunState.RUN and not consumer.new_data(),
          what='Reset handled')
    assert not consumer.get_next_data()
    assert consumer.received('data') == 3


def test_restart_by_default_runs_the_program_again_in_the_same_process(manager, peer,
                                                                       monkeypatch) -> None:
    monkeypatch.setenv('WURDE_PEER_PLAIN', '1')
    worker = peer('Restarter')
    first = next(line for line in worker.stdout.splitlines() if line.startswith('STARTED'))
    heartbeat = _heartbeat(manager, 'Restarter')
    _command(manager, heartbeat, RunState.RESTART)
    again = worker.expect('STARTED')
    assert first == again == f'STARTED {worker.process.pid}'
    assert worker.process.poll() is None

    def beat_announces_restart_ttl() -> bool:
        while heartbeat.get_next_data():
            if heartbeat.data.ttl >= 30.0:
                return True
        return False
    until(manager, beat_announces_restart_ttl, what='long TTL announced before the restart')


def test_state_callbacks_run_in_order_in_the_loop(
        manager: CommsManager, other: CommsManager) -> None:
    heartbeat = robot_object_class('Heartbeat')('heartbeat/Tester')
    other.register_consumer(heartbeat)
    entered: list[str] = []
    for state in (RunState.IDLE, RunState.RESET, RunState.RUN):
        manager.on_state(state, lambda state=state: entered.append(state.name))
    manager.step()
    assert heartbeat.wait_for_peers(20)
    for state in (RunState.IDLE, RunState.RESET):
        heartbeat.requests.state.set_value(state)
        heartbeat.publish_request()
        assert heartbeat.wait_delivered(20)
    until(manager, lambda: entered[-1:] == ['RUN'], what='callbacks')
    assert entered == ['IDLE', 'RESET', 'RUN']
    assert manager.state == RunState.RUN
    with pytest.raises(ValueError, match='Quit ends the loop'):
        manager.on_state(RunState.QUIT, lambda: None)


def test_a_module_told_to_quit_is_not_killed_by_a_late_sigint(manager, ros_domain: int) -> None:
    """The MCP sends Quit, then SIGINT when the exit is slow (a loaded machine): the module, already
    cleaned up and on its way out, must still end with status 0, not by a KeyboardInterrupt."""
    env = dict(os.environ, WURDE_PEER_LINGER='1', WURDE_PEER_PLAIN='1')
    with Peer([str(HERE / 'peer.py'), 'Leaver'], env=env) as leaver:
        leaver.expect('STATE RUN')
        _command(manager, _heartbeat(manager, 'Leaver'), RunState.QUIT)
        leaver.expect('BYE')                       # cleaned up, lingering like a slow exit
        leaver.process.send_signal(signal.SIGINT)
        leaver.process.send_signal(signal.SIGINT)
        leaver.send('exit')
        assert leaver.process.wait(timeout=30) == 0, leaver.stderr[-2000:]
    assert 'KeyboardInterrupt' not in leaver.stderr


BUSY = '''
import os, signal, sys
from wurde_core import CommsManager
manager = CommsManager('Busy')
manager.run_update()
print('busy', flush=True)
sys.stdin.readline()                    # one long step: the MCP's Quit arrives meanwhile
os.kill(os.getpid(), signal.SIGINT)     # and, the exit being slow, its SIGINT
assert manager.run_update().name == 'QUIT'
manager.clean_up()
print('commanded' if manager._told_to_quit else 'not commanded', flush=True)
'''


def test_a_module_that_sees_the_sigint_before_the_quit_command_knows_it_was_commanded(
        manager) -> None:
    """A step that runs long on a loaded machine: the MCP's Quit waits in the heartbeat's reader
    when its SIGINT ends the loop.  The clean-up finds the command, so the module does not wait
    for the MCP to acknowledge a goodbye (that wait outlasted the escalation's SIGKILL in CI)."""
    with Peer(['-c', BUSY]) as busy:
        busy.expect('busy')
        heartbeat = _heartbeat(manager, 'Busy')
        _command(manager, heartbeat, RunState.QUIT)
        assert heartbeat.wait_delivered(20, channel='request')     # in the module's reader
        busy.send('go on')
        assert busy.process.wait(timeout=30) == 0, busy.stderr[-2000:]
    assert 'not commanded' not in busy.stdout and 'commanded' in busy.stdout


STUCK = '''
import time
from wurde_core import CommsManager
manager = CommsManager('Stuck')
manager.run_update()
print('looping', flush=True)
while True:                     # a loop that never looks at the run state again
    time.sleep(0.05)
'''


def test_a_module_stuck_after_sigterm_writes_where_it_is(manager) -> None:
    """The MCP's SIGTERM comes 3 s into a Quit that has not ended, 1 s before its SIGKILL: the
    module dumps every thread's traceback to stderr as it comes (faulthandler's C handler, which
    needs no Python to run), so the module log says where it hung; our handler runs after it (the
    module is told to quit, and this loop never looks)."""
    with Peer(['-c', STUCK]) as stuck:
        stuck.expect('looping')
        stuck.process.send_signal(signal.SIGTERM)
        until(manager, lambda: 'in <module>' in stuck.stderr, what='the traceback dump')
        assert stuck.process.poll() is None
        stuck.process.kill()
    assert 'Current thread' in stuck.stderr and 'File "<string>", line' in stuck.stderr


HUNG_TEARDOWN = '''
import ctypes, os, signal, sys
from wurde_core import CommsManager
manager = CommsManager('HungTeardown')
manager.run_update()
os.kill(os.getpid(), signal.SIGINT)             # Ctrl-C: the loop ends
assert manager.run_update().name == 'QUIT'
hang = lambda: ctypes.PyDLL(None).sleep(60)      # a C call that holds the GIL, as DDS's can
if sys.argv[1] == 'ours':
    manager._system_objects[0]._disconnect = hang  # our own part of the clean-up hangs
else:
    manager.node.destroy_node = hang             # DDS's teardown hangs
manager.clean_up(exiting=sys.argv[2] == 'exiting')
print('cleaned up', flush=True)
'''


@pytest.mark.parametrize('where, exiting, status', [('dds', 'exiting', 0), ('dds', 'staying', 1),
                                                   ('ours', 'exiting', 1)])
def test_a_quitting_module_whose_clean_up_hangs_exits_with_where_it_was(manager, where, exiting,
                                                                         status) -> None:
    """A clean-up that hangs (Fast DDS's node deletion on a loaded machine, inside one C call
    that holds the GIL) does not keep a quitting module alive until the MCP's SIGKILL: it dumps
    every thread after SLOW_CLEANUP_DUMP_S and exits — with status 0 when it is the DDS
    teardown of a program that ends after its clean-up (``exiting``: the module has said goodbye
    and released its own resources), otherwise with status 1."""
    with Peer(['-c', HUNG_TEARDOWN, where, exiting]) as hung:
        assert hung.process.wait(timeout=30) == status, hung.stderr[-2000:]
    assert 'Timeout' in hung.stderr and 'in <lambda>' in hung.stderr
    assert 'cleaned up' not in hung.stdout

