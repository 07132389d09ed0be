"""Modules as tasks of one hub thread (issue 39's cooperative containers): real CommsManagers in
one rclpy context, as a cooperative container runs them.  A supplier's loop and a consumer
waiting on a trigger take turns in one thread and nothing is lost between them; each task has its
own module context; a task that raises ends alone; ``time.sleep`` in a task lets the others run."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterator
from typing import Any

import pytest
import rclpy
from rclpy.context import Context
from rclpy.signals import SignalHandlerOptions

from wurde_core import CommsManager, Trigger, cooperative, module_context
from wurde_core.interfaces import Foo
from wurde_core.ros_adaptor import WaiterGroup

#: How many data the supplier sends.
COUNT = 40
#: The longest a test waits for its hub to finish (s): a hang fails instead of blocking the suite.
DEADLINE_S = 60.0


@pytest.fixture
def context(ros_domain: int) -> Iterator[Context]:
    context = Context()
    rclpy.init(args=['wurde'], context=context, signal_handler_options=SignalHandlerOptions.NO)
    try:
        yield context
    finally:
        context.try_shutdown()


def _run(hub: cooperative.Hub, tasks: list[tuple[str, Callable[[], Any]]]) -> dict[str, Any]:
    """Run ``tasks`` (name, work) in ``hub`` in a thread of its own, each inside a module context
    as the container enters one; their results (or exceptions) by name."""
    results: dict[str, Any] = {}
    threads: set[int] = set()

    def task(name: str, work: Callable[[], Any]) -> None:
        module_context.enter(module_context.ModuleContext(name, rclpy_context=hub_context), 1000 + len(results))
        threads.add(threading.get_native_id())
        try:
            results[name] = work()
        except Exception as error:  # noqa: BLE001 - the test looks at it
            results[name] = error
        finally:
            module_context.leave()
    hub_context = hub.context
    for name, work in tasks:
        hub.spawn(name, task, name, work)
    runner = threading.Thread(target=hub.run, daemon=True)
    runner.start()
    hub.stop()                                     # ends once every task has ended
    runner.join(DEADLINE_S)
    assert not runner.is_alive(), f'the hub did not finish within {DEADLINE_S} s: {results}'
    assert threads == {runner.native_id}, 'every task ran in the hub thread'
    return results


def test_a_supplier_and_a_triggered_consumer_take_turns_in_one_thread(context: Context) -> None:
    hub = cooperative.Hub(WaiterGroup(context))

    def supplier() -> list[int]:
        manager = CommsManager('Supplier')
        manager.set_sleep_only(0.01)
        manager.set_no_heartbeat()
        out = Foo('coop_counts')
        out.set_queue_mode(True)
        manager.register_supplier(out)
        deadline = time.monotonic() + DEADLINE_S
        while not out.peers('data') and time.monotonic() < deadline:
            manager.run_update()
        sent = []
        for count in range(COUNT):
            out.data.ranges = [float(count)]
            out.publish_data()
            sent.append(count)
            manager.run_update()
        manager.clean_up(goodbye=False)
        return sent

    def consumer() -> tuple[list[int], str | None]:
        manager = CommsManager('Consumer')
        manager.set_no_sleep()
        manager.set_no_heartbeat()
        counts = Foo('coop_counts')
        counts.set_queue_mode(True)
        manager.register_consumer(counts)
        manager.register_trigger(Trigger(counts))
        seen: list[int] = []
        deadline = time.monotonic() + DEADLINE_S
        while len(seen) < COUNT and time.monotonic() < deadline:
            manager.run_update(timeout=1.0)
            while counts.get_next_data():
                seen.append(int(counts.data.ranges[0]))
        who = module_context.current()
        manager.clean_up(goodbye=False)
        return seen, who.name if who else None

    results = _run(hub, [('supplier', supplier), ('consumer', consumer)])
    assert results['supplier'] == list(range(COUNT))
    assert results['consumer'] == (list(range(COUNT)), 'consumer'), 'all data, in order, in its own context'


def test_a_task_that_raises_ends_alone_and_sleep_gives_the_turn_away(context: Context,
                                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(time, 'sleep', time.sleep)      # undone after the test
    cooperative.patch_time_sleep()
    hub = cooperative.Hub(WaiterGroup(context), quantum_s=0.0)
    order: list[str] = []

    def sleeper(name: str) -> Callable[[], int]:
        def work() -> int:
            for _ in range(5):
                order.append(name)
                started = time.monotonic()
                time.sleep(0.02)                        # the patched sleep: the other task runs
                assert time.monotonic() - started >= 0.02, 'slept at least its time'
            return 5
        return work

    def failing() -> None:
        time.sleep(0.01)
        raise RuntimeError('told to fail')

    results = _run(hub, [('a', sleeper('a')), ('b', sleeper('b')), ('bad', failing)])
    assert results['a'] == results['b'] == 5
    assert isinstance(results['bad'], RuntimeError)
    assert order[:2] == ['a', 'b'] and sorted(order) == ['a'] * 5 + ['b'] * 5
    assert all(x != y for x, y in zip(order[::2], order[1::2])), f'turns alternate: {order}'


def test_outside_a_hub_the_waits_are_the_threads_own() -> None:
    assert cooperative.current_task() is None
    assert cooperative.wait(object(), 0.01) is None
    started = time.monotonic()
    cooperative.sleep(0.01)
    assert time.monotonic() - started >= 0.01
