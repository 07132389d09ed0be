"""SenderWatch: a restarted sender is told by its session, or by its count when it has none;
and every message a manager sends says the process's session."""

from __future__ import annotations

import time
from types import SimpleNamespace

from wurde_core.channel import SESSION
from wurde_core.interfaces import Egomotion
from wurde_core.sender_watch import SenderWatch


def header(sequence: int, session: int = 0) -> SimpleNamespace:
    return SimpleNamespace(sequence=sequence, session=session)


def test_a_new_session_is_a_new_sender_whatever_its_count() -> None:
    watch = SenderWatch()
    assert [watch.take(header(n, 11)) for n in (1, 2, 3)] == [False, False, False]
    assert watch.take(header(500, 12))          # counted past the old one's: still new
    assert not watch.take(header(501, 12))
    assert not watch.take(header(1, 12))        # the same process counting again (a stream re-made)


def test_without_sessions_a_count_from_one_again_is_a_new_sender() -> None:
    watch = SenderWatch()
    assert [watch.take(header(n)) for n in (5, 6, 7)] == [False, False, False]
    assert watch.take(header(1))
    assert not watch.take(header(2))
    assert not watch.take(header(9))            # a gap is not a restart


def test_a_resumed_consumer_compares_with_what_it_saved() -> None:
    assert SenderWatch(session=11, sequence=40).take(header(41, 12))
    assert not SenderWatch(session=11, sequence=40).take(header(41, 11))
    assert SenderWatch(session=0, sequence=40).take(header(3))


def test_messages_carry_this_processs_session(manager) -> None:
    supplier, consumer = Egomotion('WatchBase'), Egomotion('WatchBase')
    manager.register_supplier(supplier)
    manager.register_consumer(consumer)
    assert SESSION != 0
    deadline = time.monotonic() + 30.0
    while not consumer.get_next_data():
        assert time.monotonic() < deadline, 'no data came back'
        supplier.publish_data()
        manager.wait(0.05)
        manager.step()
    assert consumer.data.ros_message().header.session == SESSION
