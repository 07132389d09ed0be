"""Queue mode holds for every channel, and switching it after registration takes effect."""

from __future__ import annotations

from conftest import until
from wurde_core import CommsManager
from wurde_core.interfaces import Foo
from wurde_core.naming import relative_topic
from wurde_core.qos import QUEUE_CAPACITY, stream_qos


def test_a_burst_of_info_events_reaches_a_queue_mode_consumer(
        manager: CommsManager, other: CommsManager) -> None:
    supplier = Foo('info_burst')
    supplier.set_queue_mode(True)
    other.register_supplier(supplier)
    consumer = Foo('info_burst')
    consumer.set_queue_mode(True)
    manager.register_consumer(consumer)
    assert supplier.wait_for_peers(20)
    assert consumer.wait_for_peers(20, channel='info')
    burst = 200
    for value in range(burst):
        supplier.info.max_range.set_value(float(value))
        supplier.publish_info()
    assert supplier.wait_delivered(20, channel='info')
    seen: list[float] = []

    def collect() -> bool:
        while consumer.get_next_info():
            seen.append(consumer.info.max_range.get_value())
        return len(seen) >= burst
    until(manager, collect, what=f'{burst} info events')
    assert seen == [float(v) for v in range(burst)]
    assert consumer.info_drops == 0
    assert burst < QUEUE_CAPACITY


def test_switching_to_queue_mode_after_registration_takes_effect_and_keeps_what_was_taken(
        manager: CommsManager, other: CommsManager) -> None:
    supplier = Foo('late_queue')
    supplier.set_queue_mode(True)
    other.register_supplier(supplier)
    consumer = Foo('late_queue')
    manager.register_consumer(consumer)
    assert supplier.wait_for_peers(20)
    supplier.data.ranges = [-1.0]
    supplier.publish_data()
    assert supplier.wait_delivered(20)
    manager.step()
    assert consumer.new_data()  # taken in before the switch, kept across it
    consumer.set_queue_mode(True)
    assert consumer.get_queue_mode()
    assert consumer.get_next_data() and consumer.data.ranges[0] == -1.0
    # The new, deeper subscription must be matched both ways before a burst can reach it:
    # send markers until one arrives (a volatile stream loses what precedes the match).
    seen: list[float] = []

    def marker_arrived() -> bool:
        supplier.data.ranges = [-2.0]
        supplier.publish_data()
        while consumer.get_next_data():
            seen.append(consumer.data.ranges[0])
        return bool(seen)
    until(manager, marker_arrived, what='the reconnected subscription matched')
    for value in range(50):
        supplier.data.ranges = [float(value)]
        supplier.publish_data()
    assert supplier.wait_delivered(20)

    def collect() -> bool:
        while consumer.get_next_data():
            seen.append(consumer.data.ranges[0])
        return seen[-1:] == [49.0]
    until(manager, collect, what='every event of the burst')
    assert [v for v in seen if v >= 0] == [float(v) for v in range(50)]


def test_a_restarted_supplier_first_heard_late_is_no_loss(manager: CommsManager) -> None:
    """Drops are gaps in one sender's count, and a sender is a process (``header.session``): a
    restarted supplier that the consumer first hears at its 40th message (the consumer was
    Idle, say) is a new sender joined late, not 34 lost events of the old one."""
    consumer = Foo('restarted')
    consumer.set_queue_mode(True)
    manager.register_consumer(consumer)
    writer = manager.node.create_publisher(consumer.data_type, relative_topic('restarted', 'data'),
                                           stream_qos(True))
    until(manager, lambda: writer.get_subscription_count() > 0, what='the consumer matched')
    sent = [(11, n) for n in range(1, 6)] + [(12, n) for n in range(40, 46)] + [(12, 48)]
    for session, sequence in sent:
        message = consumer.data_type()
        message.header.source, message.header.session, message.header.sequence = 'Base', session, sequence
        writer.publish(message)
    taken: list[tuple[int, int]] = []

    def collect() -> bool:
        while consumer.get_next_data():
            header = consumer.data.ros_message().header
            taken.append((header.session, header.sequence))
        return len(taken) == len(sent)
    until(manager, collect, what='every message')
    assert taken == sent
    assert consumer.data_drops == 2             # 46 and 47 of the new process: lost
