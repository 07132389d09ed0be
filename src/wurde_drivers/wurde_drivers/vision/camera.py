"""The camera base class: a template that owns opening, retrying and pacing (WURDE guide 7.2.1).

Backends implement :meth:`Camera._open`, :meth:`Camera._grab` and :meth:`Camera._close`; the
public :meth:`Camera.read` (called once per loop turn, never blocking for long) opens the device
when it is down, retries every :data:`RETRY_S` while it is absent, and closes and retries when it
vanishes (a backend raises :class:`~wurde_drivers.errors.DeviceError`), reporting each outage
once through ``report`` — so a missing or unplugged camera never ends the module. Frames are
paced to the camera's ``frameRate`` option when it has one.

Life cycle (docs/style.md 5): construct (no I/O) → :meth:`attach` (a backend that consumes streams, the
``sim`` camera, registers them) → :meth:`read` → :meth:`close` (idempotent).
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from ..errors import DeviceError
from ..ports.retry import RetryGate
from .camera_config import CameraSpec

__all__ = ['RETRY_S', 'Camera', 'Frame']

#: Seconds between two attempts to open an absent device.
RETRY_S = 1.0


@dataclasses.dataclass(frozen=True)
class Frame:
    """One image of a camera: BGR pixels (``H x W x 3`` uint8), the camera's frame index and
    the time it was taken (seconds since the epoch)."""

    camera: str
    index: int
    stamp: float
    image: NDArray[np.uint8]

    @property
    def width(self) -> int:
        return int(self.image.shape[1])

    @property
    def height(self) -> int:
        return int(self.image.shape[0])


class Camera:
    """Base of every camera type; ``type_name`` is the config's ``type`` attribute."""

    type_name: ClassVar[str] = ''

    def __init__(self, spec: CameraSpec, report: Callable[[str], object] = print,
                 note: Callable[[str], object] | None = None) -> None:
        """No I/O here: options are read and checked (:raises ConfigError:), nothing opened.

        :param report: told of troubles (absent, vanished, skipped files, ignored options);
        :param note: told of normal events (opened, back, played to the end); default ``report``.
        """
        self.spec = spec
        self.name = spec.name
        self.report = report
        self.note = note or report
        rate = spec.number('frameRate', minimum=0.0) if spec.options.get('frameRate') else 0.0
        self.period = 1.0 / rate if rate > 0 else 0.0   # frameRate 0 or unset: unpaced
        self.up = False
        self.frames = 0          # frames delivered
        self.outages = 0         # times the device was found absent or vanished (each reported)
        self.open_failures = 0   # attempts to open it that failed
        self.index = 0           # next frame index (a backend may set its own)
        self._retry = RetryGate(RETRY_S)
        self._next_frame = 0.0
        self._reported = False
        self._starved = False    # the last read found no frame ready (unpaced cameras)

    # -- what backends implement ---------------------------------------------------------------
    def _open(self) -> None:
        """Open the device. :raises DeviceError: it is absent or refuses."""
        raise NotImplementedError

    def _grab(self) -> tuple[NDArray[np.uint8], float, int | None] | None:
        """The next image, its stamp and frame index (None: count on), or None if none is ready.
        :raises DeviceError: the device vanished or stopped giving images."""
        raise NotImplementedError

    def _close(self) -> None:
        """Release the device (called only after a successful :meth:`_open`)."""

    # -- the template ---------------------------------------------------------------------------
    def attach(self, manager: Any) -> None:
        """Register what the camera consumes with the module's CommsManager (default: nothing)."""

    def read(self) -> Frame | None:
        """The next frame if one is due and ready, else None. Never raises for a device fault."""
        frame = self._read()
        self._starved = frame is None
        return frame

    def _read(self) -> Frame | None:
        now = time.monotonic()
        if not self.up:
            if not self._retry.due(now):
                return None
            try:
                self._open()
            except DeviceError as error:
                self.open_failures += 1
                self._outage(f'absent: {error}')
                return None
            self.up = True
            self.note(f'camera {self.name} ({self.type_name}) '
                      f'{"is back" if self._reported else "open"}')
            self._reported = False
        if self.period and now < self._next_frame:
            return None
        try:
            grabbed = self._grab()
        except DeviceError as error:
            self._drop()
            self._outage(f'vanished: {error}')
            return None
        if grabbed is None:
            return None
        image, stamp, index = grabbed
        if index is not None:
            self.index = index
        frame = Frame(self.name, self.index, stamp, image)
        self.index += 1
        self.frames += 1
        if self.period:   # keep the schedule; one that fell a period behind starts again
            self._next_frame += self.period
            if self._next_frame < now:
                self._next_frame = now + self.period
        return frame

    def wait_s(self) -> float:
        """How long until the next frame is due, for the module's sleep: until the next
        attempt to open it, or its paced frame; 0 for an unpaced camera that just gave one;
        ``inf`` (no idea: the loop's own sleep) when a frame was due and none was ready (a
        finished playback, a sim camera before its first pose), so nothing spins."""
        now = time.monotonic()
        if not self.up:
            return self._retry.wait_s(now)
        if self.period and now < self._next_frame:
            return self._next_frame - now
        return math.inf if self._starved else 0.0

    def _outage(self, what: str) -> None:
        self._retry.later(time.monotonic())
        if not self._reported:
            self._reported = True
            self.outages += 1
            self.report(f'camera {self.name} ({self.type_name}) {what}; retrying every {RETRY_S:g} s')

    def _drop(self) -> None:
        if self.up:
            self.up = False
            try:
                self._close()
            except DeviceError:
                pass

    def close(self) -> None:
        """Release the device; idempotent."""
        self._drop()
