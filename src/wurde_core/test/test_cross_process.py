"""wurde_core behaviours that cross a process boundary, each with two real processes."""

from __future__ import annotations

import math
import time

import pytest

from conftest import until
from wurde_core import LockedError, LockMode, RunState, Trigger
from wurde_core.interfaces import Foo, robot_object_class


def eventually(peer, command: str, pending: str, timeout: float = 20.0) -> str:
    """Repeat a peer command until its answer is no longer ``pending``; return the answer."""
    deadline = time.monotonic() + timeout
    while True:
        answer = peer.cmd(command)
        if answer != pending or time.monotonic() > deadline:
            return answer


def test_info_reaches_a_consumer_that_starts_late(manager, peer) -> None:
    server = peer('Server')
    server.cmd('supply Foo late')
    server.cmd('set_info late max_range 8.0')
    server.cmd('set_info late angle_max 3.0')
    server.cmd('publish_info late')
    foo = Foo('late')
    manager.register_consumer(foo)
    until(manager, foo.new_info, what='late info')
    assert foo.get_next_info()
    assert foo.info.max_range.get_value() == 8.0
    assert foo.info.angle_max.get_value() == 3.0
    assert foo.info.source == 'Server'


@pytest.mark.parametrize('count, expected_drops', [(1000, 0), (1500, 500)])
def test_queue_mode_loses_nothing_up_to_1000_and_counts_beyond(manager, peer, count,
                                                              expected_drops) -> None:
    foo = Foo('burst')
    foo.set_queue_mode(True)
    manager.register_consumer(foo)
    server = peer('Burst')
    server.cmd('supply Foo burst queue')
    assert int(server.cmd('wait_subscribers burst')) >= 1
    # The consumer does not look while the supplier sends everything: it falls behind.
    assert server.cmd(f'publish burst {count}') == str(count)
    assert server.cmd('wait_acked burst') == 'True'
    manager.step()
    received = []
    while foo.get_next_data():
        received.append(int(foo.data.ranges[0]))
    assert len(received) == min(count, 1000)
    assert received == list(range(count - len(received), count))
    assert foo.data_drops == expected_drops


def test_latest_mode_keeps_only_the_newest(manager, peer) -> None:
    foo = Foo('latest')
    manager.register_consumer(foo)
    server = peer('Latest')
    server.cmd('supply Foo latest')
    server.cmd('wait_subscribers latest')
    server.cmd('publish latest 50')
    server.cmd('wait_acked latest')
    until(manager, lambda: foo.new_data() and foo.data_drops == 0 and foo.received('data')
          and foo.get_next_data() and foo.data.ranges[0] == 49.0, what='newest event')
    assert not foo.new_data() and not foo.get_next_data()


def test_locks_are_held_by_the_supplier_and_enforced_in_both_processes(manager, peer) -> None:
    server = peer('Owner')
    server.cmd('supply Foo locked')
    server.cmd('lock locked max_range SUPPLIERS')
    server.cmd('lock locked angle_min PROCESS Tester')
    server.cmd('publish_info locked')
    foo = Foo('locked')
    manager.register_consumer(foo)
    until(manager, lambda: foo.new_info(), what='info with locks')
    foo.get_next_info()
    assert foo.locks() == {'max_range': (LockMode.SUPPLIERS, ''),
                           'angle_min': (LockMode.PROCESS, 'Tester')}
    with pytest.raises(LockedError, match='max_range is locked to suppliers only'):
        foo.requests.max_range.set_value(1.0)
    foo.requests.angle_min.set_value(0.5)  # locked to this very process: allowed
    foo.requests.angle_max.set_value(2.5)  # not locked
    until(manager, lambda: foo.peers() > 0, what='request matched')
    assert foo.publish_request()
    assert eventually(server, 'requests locked', '-') == 'Tester:angle_max=2.5,angle_min=0.5'

    # A process that ignores the lock is refused by the supplier all the same.
    rogue = Foo('locked')
    rogue_manager = type(manager)('Rogue')
    try:
        rogue_manager.set_no_sleep()
        rogue_manager.register_consumer(rogue)
        rogue.requests.angle_min.set_value(9.0)  # Rogue has not seen the locks yet
        until(rogue_manager, lambda: rogue.peers() > 0,
              what='rogue matched')
        rogue.publish_request()
        assert eventually(server, 'refused locked', '0') == '1'
        assert server.cmd('requests locked') == '-'
    finally:
        rogue_manager.clean_up()


def test_states_are_commanded_from_another_process(manager, peer) -> None:
    worker = peer('Worker')
    worker.cmd('supply Foo work')
    heartbeat = robot_object_class('Heartbeat')('heartbeat/Worker')
    heartbeat.set_queue_mode(True)
    manager.register_consumer(heartbeat)

    def described() -> bool:  # queue mode: a late consumer gets the past descriptions too
        while heartbeat.get_next_info():
            if heartbeat.info.interfaces.get_value() == ['Foo']:
                return True
        return False
    until(manager, described, what='worker description with its supplier')
    assert heartbeat.info.state.get_value() == RunState.RUN
    assert heartbeat.info.streams.get_value() == ['work']
    pid = heartbeat.info.pid.get_value()
    assert pid == worker.process.pid

    def command(state: RunState) -> None:
        until(manager, lambda: heartbeat.peers() > 0, what='match')
        heartbeat.requests.state.set_value(state)
        heartbeat.publish_request()

    command(RunState.IDLE)
    worker.expect('STATE IDLE')  # the loop waits in run_update (see test_run_states.py)
    command(RunState.RESET)
    worker.expect('STATE RESET')
    worker.expect('STATE RUN')  # the peer's Reset callback is done: back to Run by itself
    assert worker.cmd('publish work 3') == '3'
    command(RunState.QUIT)
    worker.expect('STATE QUIT')
    worker.expect('BYE')
    assert worker.process.wait(timeout=20) == 0


def test_heartbeat_carries_ttl_twice_the_sleep(manager, peer) -> None:
    worker = peer('Beater')
    heartbeat = robot_object_class('Heartbeat')('heartbeat/Beater')
    heartbeat.set_queue_mode(True)
    manager.register_consumer(heartbeat)
    beats = []

    def collect() -> bool:
        while heartbeat.get_next_data():
            beats.append((heartbeat.data.ttl, heartbeat.data.timestamp))
        return len(beats) >= 5

    until(manager, collect, what='five heartbeats')
    assert all(ttl == pytest.approx(0.02) for ttl, _ in beats)  # peer: set_sleep(0.01)
    assert worker.process.poll() is None


def test_sigterm_ends_the_loop_and_cleans_up(manager, peer) -> None:
    worker = peer('Terminated')
    heartbeat = robot_object_class('Heartbeat')('heartbeat/Terminated')
    heartbeat.set_queue_mode(True)
    manager.register_consumer(heartbeat)
    until(manager, heartbeat.new_info, what='description')
    worker.process.terminate()
    assert worker.process.wait(timeout=20) == 0
    worker.expect('BYE')

    def said_quit() -> bool:
        while heartbeat.get_next_info():
            if heartbeat.info.state.get_value() == RunState.QUIT:
                return True
        return False
    until(manager, said_quit, what='goodbye with state Quit')


def test_and_trigger_waits_for_every_object_or_trigger_for_any(manager, peer) -> None:
    a, b = Foo('trig_a'), Foo('trig_b')
    a.set_queue_mode(True)
    b.set_queue_mode(True)
    manager.register_consumer(a)
    manager.register_consumer(b)
    manager.register_trigger(Trigger(a, b))
    server = peer('Triggers')
    server.cmd('supply Foo trig_a queue')
    server.cmd('supply Foo trig_b queue')
    server.cmd('wait_subscribers trig_a')
    server.cmd('wait_subscribers trig_b')
    manager.run_update(timeout=0.2)  # take in the info both suppliers published at start

    server.cmd('publish trig_a 1')
    start = time.monotonic()
    manager.run_update(timeout=1.0)
    assert time.monotonic() - start >= 0.95, 'AND trigger fired with only one object fed'
    assert a.new_data() and not b.new_data()

    server.cmd('publish trig_b 1')
    start = time.monotonic()
    manager.run_update(timeout=20.0)
    assert time.monotonic() - start < 19.0, 'AND trigger did not fire with both objects fed'
    assert b.new_data()

    for trigger in manager.triggers():
        manager.unregister_trigger(trigger)
    manager.register_trigger(Trigger(a))
    manager.register_trigger(Trigger(b))
    server.cmd('publish trig_b 1')
    start = time.monotonic()
    manager.run_update(timeout=20.0)
    assert time.monotonic() - start < 19.0, 'OR of triggers did not fire for one of them'


def test_foo_angles_survive_the_wire_exactly(manager, peer) -> None:
    server = peer('Exact')
    server.cmd('supply Foo exact')
    server.cmd(f'set_info exact angle_max {math.pi!r}')
    server.cmd('publish_info exact')
    foo = Foo('exact')
    manager.register_consumer(foo)
    until(manager, foo.new_info, what='info')
    foo.get_next_info()
    assert foo.info.angle_max.get_value() == math.pi
