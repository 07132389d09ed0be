"""The Eye's one frame source: the latest image as it is shown, shared by the module's loop (the
writer) and the displays (the window in the loop's thread, the web page in its server's threads).

A :class:`Frame` is the decoded image after the display settings (scale, overlay) were applied;
it is immutable, so a reader may keep and encode it while the loop puts the next one. No ROS
here: the module feeds it pixels it decoded with :mod:`wurde_drivers.image_codec`.
"""

from __future__ import annotations

import dataclasses
import threading
from typing import cast

import cv2
import numpy as np
import numpy.typing as npt

__all__ = ['MAX_SCALE', 'DisplaySettings', 'Frame', 'FrameStore', 'compose', 'ppm']

#: Largest display scale factor accepted (a 320x240 image shown 8 times is 2560x1920).
MAX_SCALE = 8.0


@dataclasses.dataclass(frozen=True)
class DisplaySettings:
    """What ImageDisplay's info says and its requests change (see the interface)."""

    title: str = 'Eye'
    stream: str = ''
    visible: bool = True
    scale: float = 1.0
    overlay: str = ''


@dataclasses.dataclass(frozen=True)
class Frame:
    """One image as shown: ``index`` counts the frames the Eye took in (1, 2, ...);
    ``source_index`` is the camera's ``frame_index``; ``rgb`` is (height, width, 3) uint8."""

    index: int
    source_index: int
    rgb: npt.NDArray[np.uint8]

    @property
    def width(self) -> int:
        return int(self.rgb.shape[1])

    @property
    def height(self) -> int:
        return int(self.rgb.shape[0])


def compose(rgb: npt.NDArray[np.uint8], settings: DisplaySettings) -> npt.NDArray[np.uint8]:
    """``rgb`` scaled by ``settings.scale`` (nearest pixel: image pixels stay visible as they are)
    with ``settings.overlay`` drawn in the top-left corner (white on a dark band)."""
    out = rgb
    if settings.scale != 1.0:
        height, width = rgb.shape[:2]
        size = (max(1, round(width * settings.scale)), max(1, round(height * settings.scale)))
        out = cast(npt.NDArray[np.uint8], cv2.resize(rgb, size, interpolation=cv2.INTER_NEAREST))
    if settings.overlay:
        out = out.copy() if out is rgb else out
        font, font_scale, thickness = cv2.FONT_HERSHEY_SIMPLEX, 0.5, 1
        (text_w, text_h), base = cv2.getTextSize(settings.overlay, font, font_scale, thickness)
        band = out[:text_h + base + 6, :text_w + 8]
        band[...] = band // 3
        cv2.putText(out, settings.overlay, (4, text_h + 3), font, font_scale, (255, 255, 255), thickness,
                    cv2.LINE_AA)
    return out


def ppm(rgb: npt.NDArray[np.uint8]) -> bytes:
    """Binary PPM (P6) of RGB pixels: what Tk's PhotoImage reads without Pillow."""
    height, width = rgb.shape[:2]
    return b'P6\n%d %d\n255\n' % (width, height) + np.ascontiguousarray(rgb).tobytes()


class FrameStore:
    """The latest :class:`Frame` and the display settings; safe across threads.

    The loop calls :meth:`put`; any thread calls :meth:`latest`, :meth:`wait_newer` or
    :meth:`png` (encoded once per frame, however many clients fetch it).
    """

    def __init__(self, settings: DisplaySettings) -> None:
        self._changed = threading.Condition()
        self._frame: Frame | None = None
        self._raw: tuple[npt.NDArray[np.uint8], int] | None = None
        self._settings = settings
        self._png: tuple[int, bytes] | None = None
        self._closed = False

    @property
    def settings(self) -> DisplaySettings:
        with self._changed:
            return self._settings

    def set_settings(self, settings: DisplaySettings) -> Frame | None:
        """New settings; the last image is composed again with them (a new frame) if there is one."""
        with self._changed:
            self._settings = settings
            raw = self._raw
        return self.put(*raw) if raw is not None else None

    def put(self, rgb: npt.NDArray[np.uint8], source_index: int) -> Frame:
        """Compose decoded pixels with the current settings and make them the latest frame."""
        with self._changed:
            settings = self._settings
            index = self._frame.index + 1 if self._frame else 1
        shown = compose(rgb, settings)
        shown.flags.writeable = False
        frame = Frame(index, int(source_index), shown)
        with self._changed:
            self._raw = (rgb, int(source_index))
            self._frame = frame
            self._changed.notify_all()
        return frame

    def latest(self) -> Frame | None:
        """The latest frame, or None before the first."""
        with self._changed:
            return self._frame

    def wait_newer(self, index: int, timeout: float) -> Frame | None:
        """The latest frame once its index is above ``index``; None after ``timeout`` seconds
        (or once the store is closed) without one."""
        with self._changed:
            self._changed.wait_for(
                lambda: self._closed or (self._frame is not None and self._frame.index > index),
                timeout)
            frame = self._frame
        return frame if frame is not None and frame.index > index else None

    def png(self, frame: Frame) -> bytes:
        """PNG bytes of ``frame`` (lossless, so a page shows the exact pixels)."""
        with self._changed:
            if self._png is not None and self._png[0] == frame.index:
                return self._png[1]
        ok, encoded = cv2.imencode('.png', cv2.cvtColor(frame.rgb, cv2.COLOR_RGB2BGR),
                                   [cv2.IMWRITE_PNG_COMPRESSION, 1])
        if not ok:              # cv2 reports failure by a flag; PNG of uint8 RGB cannot fail
            raise RuntimeError('PNG encoding failed')
        data = encoded.tobytes()
        with self._changed:
            if self._frame is not None and self._frame.index == frame.index:
                self._png = (frame.index, data)
        return data

    def close(self) -> None:
        """Wake every waiting reader (the module is ending); idempotent."""
        with self._changed:
            self._closed = True
            self._changed.notify_all()
