"""Helpers for the end-to-end tests of the simulated robot: configs in tmp, an observer module."""

from __future__ import annotations

import pathlib
import time
from collections.abc import Callable, Iterable
from typing import Any

from lxml import etree
from wurde_core import CommsManager
from wurde_core.interfaces import robot_object_class

ROOT = pathlib.Path(__file__).resolve().parents[3]
SIM = ROOT / 'config' / 'sim'
MAPS = ROOT / 'config' / 'maps'


def sim_config(directory: pathlib.Path, *, top: dict[str, str] | None = None,
               elements: dict[str, dict[str, str]] | None = None, start: str | None = None) -> pathlib.Path:
    """A copy of config/sim (sim-config, mcp-config, mappings) in ``directory``, with changes.

    ``top`` changes attributes of <sim-config>, ``elements`` those of its children by tag;
    the map path is made absolute so the copy works from anywhere.
    """
    tree = etree.parse(str(SIM / 'sim-config.xml'))
    root = tree.getroot()
    for key, value in (top or {}).items():
        root.set(key, value)
    map_node = root.find('map')
    assert map_node is not None
    map_node.set('file', str((SIM / map_node.get('file')).resolve()))
    if start is not None:
        map_node.set('start', start)
    for tag, attributes in (elements or {}).items():
        node = root.find(tag)
        assert node is not None, tag
        for key, value in attributes.items():
            node.set(key, value)
    directory.mkdir(parents=True, exist_ok=True)
    tree.write(str(directory / 'sim-config.xml'))
    for name in ('mcp-config.xml', 'mcp-mappings.xml'):
        (directory / name).write_bytes((SIM / name).read_bytes())
    return directory / 'sim-config.xml'


class Observer:
    """A module in the test process that consumes streams in queue mode and keeps every event."""

    def __init__(self, streams: dict[str, str], *, queue: bool = True, namespace: str = '/',
                 sim_time: bool = False) -> None:
        """``namespace``: observe the robot started there; ``sim_time``: the observer's own
        clock (``manager.now()``) follows the simulator's ``/clock``."""
        self.manager = CommsManager('Observer')
        ros_arguments = ['-r', f'__ns:={namespace}'] if namespace != '/' else []
        ros_arguments += ['-p', 'use_sim_time:=true'] if sim_time else []
        if ros_arguments:
            self.manager.parse_options(['observer', '--ros-args', *ros_arguments])
        self.manager.set_no_sleep()
        self.objects = {}
        for stream, interface in streams.items():
            obj = robot_object_class(interface)(stream)
            obj.set_queue_mode(queue)
            self.manager.register_consumer(obj)
            self.objects[stream] = obj
        self.events: dict[str, list[tuple[float, Any]]] = {s: [] for s in streams}
        self.infos: dict[str, Any] = {}

    def obj(self, stream: str) -> Any:
        return self.objects[stream]

    def pump(self) -> None:
        self.manager.step()
        for stream, obj in self.objects.items():
            while obj.get_next_data():
                message = obj.data.ros_message()
                self.events[stream].append((obj.data.timestamp.get_seconds(), message))
            while obj.get_next_info():
                self.infos[stream] = obj.info.ros_message()

    def until(self, predicate: Callable[['Observer'], bool], what: str, timeout: float = 60.0) -> None:
        deadline = time.monotonic() + timeout
        while True:
            self.pump()  # each received event is a message of its own: kept as it is
            if predicate(self):
                return
            if time.monotonic() > deadline:
                counts = {s: len(e) for s, e in self.events.items()}
                raise AssertionError(f'{what}: not within {timeout} s; events so far: {counts}')
            self.manager.wait(0.02)

    def stamps(self, stream: str) -> list[float]:
        return [stamp for stamp, _ in self.events[stream]]

    def beats(self, module: str) -> int:
        """Heartbeats of ``module`` seen so far (observe :func:`heartbeat` ``(module)``)."""
        return len(self.events[HEARTBEAT + module])

    def quiet_span(self, module: str, what: str, *, turns: int = 3, timeout: float = 30.0) -> float:
        """Wait while ``module`` sends ``turns`` more heartbeats; return the wall time this began.

        A "nothing is published while the device is silent" check is proven, not waited for:
        the span is measured in the module's own loop turns (each one a chance to publish), and
        :func:`assert_none_between` checks the stamps once events from after the silence have
        arrived — one writer, delivered in order, so nothing of the span is still on its way.
        """
        start, seen = time.time(), self.beats(module)
        self.until(lambda o: o.beats(module) >= seen + turns, what, timeout)
        return start

    def request(self, stream: str, **values: Any) -> None:
        obj = self.objects[stream]
        for name, value in values.items():
            getattr(obj.requests, name).set_value(value)
        obj.publish_request()

    def close(self) -> None:
        self.manager.clean_up()


HEARTBEAT = 'heartbeat/'


def heartbeat(module: str) -> dict[str, str]:
    """The stream of ``module``'s heartbeat, for an :class:`Observer` (its beats are loop turns)."""
    return {HEARTBEAT + module: 'Heartbeat'}


def assert_none_between(stamps: Iterable[float], start: float, end: float, what: str) -> None:
    """No event of ``stamps`` is stamped inside ``(start, end)`` (wall-clock seconds)."""
    inside = [stamp for stamp in stamps if start < stamp < end]
    assert not inside, f'{what}: {len(inside)} events stamped between {start:.3f} and {end:.3f}'


def median_interval(stamps: Iterable[float]) -> float:
    values = sorted(stamps)
    gaps = sorted(b - a for a, b in zip(values, values[1:]))
    return gaps[len(gaps) // 2]
