"""A person's mouse and keyboard on an X display, through the XTest extension (libXtst, which
Xvfb serves; ``tools/setup_system.sh`` installs libxtst6), loaded with ctypes: no xdotool."""

from __future__ import annotations

import ctypes

_X11 = ctypes.CDLL('libX11.so.6')
_XTST = ctypes.CDLL('libXtst.so.6')
_X11.XOpenDisplay.restype = ctypes.c_void_p
_X11.XOpenDisplay.argtypes = [ctypes.c_char_p]
_X11.XCloseDisplay.argtypes = [ctypes.c_void_p]
_X11.XFlush.argtypes = [ctypes.c_void_p]
_X11.XSync.argtypes = [ctypes.c_void_p, ctypes.c_int]
_X11.XKeysymToKeycode.argtypes = [ctypes.c_void_p, ctypes.c_ulong]
_X11.XKeysymToKeycode.restype = ctypes.c_ubyte
_XTST.XTestFakeMotionEvent.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.c_int, ctypes.c_int,
                                       ctypes.c_ulong]
_XTST.XTestFakeButtonEvent.argtypes = [ctypes.c_void_p, ctypes.c_uint, ctypes.c_int, ctypes.c_ulong]
_XTST.XTestFakeKeyEvent.argtypes = [ctypes.c_void_p, ctypes.c_uint, ctypes.c_int, ctypes.c_ulong]


class FakeInput:
    """Clicks and key presses on ``display`` (``":N"``); a context manager."""

    def __init__(self, display: str) -> None:
        self._display = _X11.XOpenDisplay(display.encode())
        if not self._display:
            raise AssertionError(f'cannot open X display {display}')

    def click(self, x: int, y: int) -> None:
        """Move the pointer to screen pixel (x, y) and click the left button there."""
        _XTST.XTestFakeMotionEvent(self._display, -1, x, y, 0)
        _XTST.XTestFakeButtonEvent(self._display, 1, 1, 0)
        _XTST.XTestFakeButtonEvent(self._display, 1, 0, 0)
        _X11.XSync(self._display, 0)

    def key(self, keysym: int) -> None:
        """Press and release the key of ``keysym`` (an X keysym number, e.g. 0x61 for 'a')."""
        code = _X11.XKeysymToKeycode(self._display, keysym)
        _XTST.XTestFakeKeyEvent(self._display, code, 1, 0)
        _XTST.XTestFakeKeyEvent(self._display, code, 0, 0)
        _X11.XSync(self._display, 0)

    def close(self) -> None:
        if self._display:
            _X11.XCloseDisplay(self._display)
            self._display = None

    def __enter__(self) -> 'FakeInput':
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
