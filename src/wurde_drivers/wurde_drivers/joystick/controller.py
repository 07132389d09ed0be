"""The guide's GameController: a joystick's axes and buttons by name (WURDE guide 1.1.5, 7.9).

BlindTeleop declares ``GameController joystick;``, calls ``configureJoystick("joystick-config.xml",
joystick)`` and then reads ``joystick.axis("translate")`` (raw, -32767 .. 32767) and
``joystick.button("quit")`` in its loop.  Here :func:`configure_joystick` does the same, and the
program calls :meth:`GameController.update` once per loop to take in what the device sent.

The controller never answers from stale input: until the device has sent its state (the init
events a kernel sends on open) :attr:`ready` is False and every axis reads 0 and every button
False; when the device vanishes the state is forgotten the same way until it comes back.
A name the configuration does not have reads 0 / False (reported once).
"""

from __future__ import annotations

import os
from collections.abc import Callable

from .codec import JsEvent
from .config import JoystickLayout, layout_named, load_joystick_config
from .device import DeviceState, JoystickDriver

__all__ = ['GameController', 'configure_joystick']


class GameController:
    """Named axes and buttons of one joystick.  Construct (no I/O), :meth:`configure`,
    :meth:`open`, then :meth:`update` each loop; :meth:`close` at the end."""

    def __init__(self, *, report: Callable[[str], object] | None = None) -> None:
        self.report = report or (lambda message: None)
        self.layout = JoystickLayout('unconfigured', {}, {})
        self.device: JoystickDriver | None = None
        self._axes: dict[int, int] = {}
        self._buttons: dict[int, bool] = {}
        self._ready = False
        self._unknown: set[str] = set()

    # -- set-up ----------------------------------------------------------------------------------
    def configure(self, layout: JoystickLayout) -> None:
        """Use ``layout``'s names from now on."""
        self.layout = layout
        self._unknown.clear()

    def open(self, path: str, *, retry_s: float = 1.0) -> None:
        """Read the joystick at ``path`` (opened, and reopened, by :meth:`update`)."""
        self.close()
        self.device = JoystickDriver(path, retry_s=retry_s, report=self.report)

    def close(self) -> None:
        """Close the device (idempotent) and forget its state."""
        if self.device is not None:
            self.device.close()
        self._forget()

    # -- the loop --------------------------------------------------------------------------------
    def update(self, now: float | None = None) -> list[JsEvent]:
        """Take in what the device sent since the last call; the events, in order."""
        if self.device is None:
            return []
        events = self.device.poll(now)
        if self.device.state != DeviceState.LIVE:
            self._forget()
            return events
        self.apply(events)
        return events

    def apply(self, events: list[JsEvent]) -> None:
        """Apply events (as :meth:`update` does with the device's)."""
        for event in events:
            if event.is_axis:
                self._axes[event.number] = event.value
            else:
                self._buttons[event.number] = event.value != 0
            self._ready = True

    @property
    def ready(self) -> bool:
        """True while the joystick is there and has told its state."""
        return self._ready

    # -- the guide's accessors -------------------------------------------------------------------
    def axis(self, name: str) -> int:
        """The axis called ``name``: -32767 .. 32767 (0 while not :attr:`ready`)."""
        number = self._number(self.layout.axes, name, 'axis')
        return self._axes.get(number, 0) if number is not None and self._ready else 0

    def button(self, name: str) -> bool:
        """Whether the button called ``name`` is pressed (False while not :attr:`ready`)."""
        number = self._number(self.layout.buttons, name, 'button')
        return self._buttons.get(number, False) if number is not None and self._ready else False

    # -- internals -------------------------------------------------------------------------------
    def _number(self, names: dict[str, int], name: str, kind: str) -> int | None:
        number = names.get(name)
        if number is None and f'{kind}:{name}' not in self._unknown:
            self._unknown.add(f'{kind}:{name}')
            self.report(f'joystick "{self.layout.name}" has no {kind} named "{name}": it reads as '
                        'released')
        return number

    def _forget(self) -> None:
        self._axes.clear()
        self._buttons.clear()
        self._ready = False


def configure_joystick(config: str | os.PathLike[str], joystick: GameController,
                       name: str | None = None) -> JoystickLayout:
    """The guide's ``configureJoystick(config, joystick)``: read the file and give ``joystick``
    the layout called ``name`` (the first when None).

    :raises ConfigError: a bad file (file, line and reason) or no joystick of that name.
    """
    layout = layout_named(load_joystick_config(config), name)
    joystick.configure(layout)
    return layout
