"""The joystick device reader and GameController against real FIFO bytes: the emulator's, and
bytes written by hand (partial records, unknown types); a device that is not there yet, vanishes
and comes back is reported and retried, and its stale state is never read."""

from __future__ import annotations

import os
import pathlib
import struct
import time
import tty
from collections.abc import Callable, Iterator

import pytest
from wurde_drivers.errors import DriverError
from wurde_drivers.joystick.codec import JS_EVENT_AXIS, JS_EVENT_BUTTON, JsEvent, encode_event
from wurde_drivers.joystick.config import JoystickLayout
from wurde_drivers.joystick.controller import GameController
from wurde_drivers.joystick.device import DeviceState, JoystickDevice
from wurde_drivers.joystick.emulator import JoystickEmulator

LAYOUT = JoystickLayout('test pad', {'rotate': 0, 'translate': 1}, {'stop': 4, 'quit': 5})


def until(predicate: Callable[[], bool], poll: Callable[[], object], what: str,
          timeout: float = 10.0) -> None:
    """Poll the reader until ``predicate`` holds; fail after ``timeout``."""
    deadline = time.monotonic() + timeout
    while not predicate():
        assert time.monotonic() < deadline, f'{what}: not within {timeout} s'
        poll()
        time.sleep(0.005)


class RecordingController(GameController):
    """A GameController that keeps what it reports."""

    def __init__(self) -> None:
        self.reports: list[str] = []
        super().__init__(report=self.reports.append)


@pytest.fixture
def controller() -> Iterator[RecordingController]:
    joystick = RecordingController()
    joystick.configure(LAYOUT)
    yield joystick
    joystick.close()


def test_absent_then_live_then_vanished_then_back(tmp_path: pathlib.Path,
                                                  controller: RecordingController) -> None:
    path = str(tmp_path / 'js0')
    reports = controller.reports
    controller.open(path, retry_s=0.02)
    controller.update()
    assert controller.device is not None and controller.device.state == DeviceState.ABSENT
    assert not controller.ready and controller.axis('translate') == 0
    assert 'not there' in reports[-1]

    with JoystickEmulator(path, axes=6, buttons=8) as stick:
        stick.set_axis(1, -20000)            # before anyone opens it: sent as an init event
        until(lambda: controller.ready, controller.update, 'the init events')
        assert controller.axis('translate') == -20000 and controller.axis('rotate') == 0
        assert not controller.button('stop')
        stick.set_button(4, True)
        stick.set_axis(0, 12345)
        until(lambda: controller.button('stop') and controller.axis('rotate') == 12345,
              controller.update, 'the live events')
        assert stick.connections == 1
    # The emulator closed its end and removed the FIFO: the device vanished.
    until(lambda: not controller.ready, controller.update, 'the device gone')
    assert controller.device.state == DeviceState.ABSENT and controller.device.vanished == 1
    assert controller.axis('translate') == 0 and not controller.button('stop')   # nothing stale
    assert any('gone' in report for report in reports)

    with JoystickEmulator(path, axes=6, buttons=8) as stick:
        stick.set_button(5, True)
        until(lambda: controller.ready and controller.button('quit'), controller.update,
              'the device back')
        assert controller.axis('translate') == 0 and not controller.button('stop')
        assert controller.device.opens >= 2
    assert controller.axis('nosuch') == 0
    assert 'no axis named "nosuch"' in reports[-1]


def test_a_new_reader_is_greeted_with_the_current_state(tmp_path: pathlib.Path) -> None:
    path = str(tmp_path / 'js0')
    with JoystickEmulator(path, axes=2, buttons=2) as stick:
        stick.set_axis(1, 300)
        for round_ in (1, 2):
            device = JoystickDevice(path, retry_s=0.02)
            got: list[JsEvent] = []
            until(lambda: len(got) >= 4, lambda: got.extend(device.poll()), f'init round {round_}')
            assert all(event.init for event in got[:4])
            assert [(e.kind, e.number, e.value) for e in got[:4]] == [
                (JS_EVENT_AXIS, 0, 0), (JS_EVENT_AXIS, 1, 300), (JS_EVENT_BUTTON, 0, 0),
                (JS_EVENT_BUTTON, 1, 0)]
            device.close()
            assert stick.wait_connected(round_, 5.0)
            # A FIFO's writer learns of a reader's close only by looking (every 10 ms); a reader
            # that reopened before that would share the old pipe and get no init events.
            assert stick.wait_disconnected(round_, 5.0)


def test_partial_records_wait_and_unknown_types_are_dropped(tmp_path: pathlib.Path) -> None:
    path = tmp_path / 'js0'
    os.mkfifo(path)
    device = JoystickDevice(str(path), retry_s=0.02)
    assert device.poll() == [] and device.state == DeviceState.WAITING   # open, no writer yet
    writer = os.open(path, os.O_WRONLY | os.O_NONBLOCK)
    try:
        record = encode_event(JsEvent(JS_EVENT_AXIS, 1, -5, 77))
        os.write(writer, record[:3])
        until(lambda: device.state == DeviceState.LIVE, device.poll, 'the first bytes')
        assert device.decoder.pending == 3
        os.write(writer, record[3:] + struct.pack('<IhBB', 1, 1, 0x04, 0) + encode_event(
            JsEvent(JS_EVENT_BUTTON, 2, 1, 78)))
        got: list[JsEvent] = []
        until(lambda: len(got) >= 2, lambda: got.extend(device.poll()), 'the rest')
        assert got == [JsEvent(JS_EVENT_AXIS, 1, -5, 77), JsEvent(JS_EVENT_BUTTON, 2, 1, 78)]
        assert device.dropped == 1 and device.decoder.pending == 0
    finally:
        os.close(writer)
    until(lambda: device.state == DeviceState.ABSENT, device.poll, 'the writer gone')
    assert device.vanished == 1
    device.poll()                     # the FIFO is still there: reopened, waiting for a writer
    assert device.state == DeviceState.WAITING
    device.close()


def test_the_emulator_refuses_a_path_that_is_not_a_fifo(tmp_path: pathlib.Path) -> None:
    plain = tmp_path / 'file'
    plain.write_text('')
    with pytest.raises(DriverError, match='not a FIFO'):
        JoystickEmulator(str(plain)).start()
    with JoystickEmulator(str(tmp_path / 'js'), axes=2, buttons=2) as stick:
        with pytest.raises(ValueError):
            stick.set_axis(2, 0)
        with pytest.raises(ValueError):
            stick.set_axis(0, 40000)
        with pytest.raises(ValueError):
            stick.set_button(2, True)


def test_a_pseudo_terminal_carries_the_records_and_its_hang_up_is_a_vanished_device() -> None:
    """A pty in raw mode (as the serial emulators make them) is read like the kernel's device;
    when its master closes the reader sees the device gone."""
    master, slave = os.openpty()
    tty.setraw(slave)                      # raw: the line discipline must not touch the bytes
    path = os.ttyname(slave)
    os.close(slave)
    device = JoystickDevice(path, retry_s=0.02)
    try:
        # bytes a cooked terminal would change: CR, LF, ^D, ^C, ^S
        sent = [JsEvent(JS_EVENT_AXIS, 10, 0x0d04, 0x0a0d0313, init=True),
                JsEvent(JS_EVENT_BUTTON, 4, 1, 0x13)]
        device.poll()
        assert device.state == DeviceState.WAITING
        data = b''.join(encode_event(event) for event in sent)
        os.write(master, data[:5])
        os.write(master, data[5:])
        got: list[JsEvent] = []
        until(lambda: len(got) >= 2, lambda: got.extend(device.poll()), 'the pty records')
        assert got == sent
    finally:
        os.close(master)
    until(lambda: device.state == DeviceState.ABSENT, device.poll, 'the hang-up')
    assert device.vanished == 1
    device.close()
