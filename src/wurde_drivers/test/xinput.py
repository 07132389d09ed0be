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
_X11.XDefaultRootWindow.argtypes = [ctypes.c_void_p]
_X11.XDefaultRootWindow.restype = ctypes.c_ulong
_X11.XInternAtom.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_int]
_X11.XInternAtom.restype = ctypes.c_ulong
_X11.XQueryTree.argtypes = [ctypes.c_void_p, ctypes.c_ulong, ctypes.POINTER(ctypes.c_ulong),
                            ctypes.POINTER(ctypes.c_ulong),
                            ctypes.POINTER(ctypes.POINTER(ctypes.c_ulong)),
                            ctypes.POINTER(ctypes.c_uint)]
_X11.XFree.argtypes = [ctypes.c_void_p]
_X11.XSendEvent.argtypes = [ctypes.c_void_p, ctypes.c_ulong, ctypes.c_int, ctypes.c_long,
                            ctypes.c_void_p]
CLIENT_MESSAGE = 33


class _ClientMessage(ctypes.Structure):
    """Xlib's XClientMessageEvent."""

    _fields_ = [('type', ctypes.c_int), ('serial', ctypes.c_ulong), ('send_event', ctypes.c_int),
                ('display', ctypes.c_void_p), ('window', ctypes.c_ulong),
                ('message_type', ctypes.c_ulong), ('format', ctypes.c_int),
                ('data', ctypes.c_long * 5)]


class _Event(ctypes.Union):
    """Xlib's XEvent: 24 longs, whatever the event."""

    _fields_ = [('client', _ClientMessage), ('pad', ctypes.c_long * 24)]


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

    def close_windows(self) -> int:
        """Ask every top-level window to close, as a window manager's close button does (a
        WM_DELETE_WINDOW message); returns how many were asked."""
        root = _X11.XDefaultRootWindow(self._display)
        protocols = _X11.XInternAtom(self._display, b'WM_PROTOCOLS', 0)
        delete = _X11.XInternAtom(self._display, b'WM_DELETE_WINDOW', 0)
        parent, root_back = ctypes.c_ulong(), ctypes.c_ulong()
        children, count = ctypes.POINTER(ctypes.c_ulong)(), ctypes.c_uint()
        _X11.XQueryTree(self._display, root, ctypes.byref(root_back), ctypes.byref(parent),
                        ctypes.byref(children), ctypes.byref(count))
        windows = [children[i] for i in range(count.value)]
        if children:
            _X11.XFree(children)
        for window in windows:
            event = _Event()
            event.client.type, event.client.window = CLIENT_MESSAGE, window
            event.client.message_type, event.client.format = protocols, 32
            event.client.data[0], event.client.data[1] = delete, 0
            _X11.XSendEvent(self._display, window, 0, 0, ctypes.byref(event))
        _X11.XSync(self._display, 0)
        return len(windows)

    def close(self) -> None:
        if self._display:
            _X11.XCloseDisplay(self._display)
            self._display = None

    def __enter__(self) -> 'FakeInput':
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
