"""The Eye's window: a Tk toplevel on the X display, drawn from the module's loop.

Tk is not thread-safe, so the window lives in the loop's thread: :meth:`TkWindow.show` puts a
frame into it and :meth:`TkWindow.pump` (once per loop turn) lets Tk draw and deliver events —
no second thread, no Tk main loop. The image is a PhotoImage fed binary PPM (no Pillow). The
window opens at the screen's top-left corner; a left click reports the image pixel under the
pointer (the scale divided out), a key press its X keysym number; closing the window ends the
module (``on_close``).
"""

from __future__ import annotations

import os
import tkinter
from collections.abc import Callable

from .frames import Frame, FrameStore, ppm
from .status import DisplayStatus

__all__ = ['TkWindow', 'WindowError', 'display_available']


class WindowError(RuntimeError):
    """No window can be opened (no X display, or Tk cannot reach it)."""


def display_available() -> bool:
    """Whether ``DISPLAY`` names an X display (the window is tried only then)."""
    return bool(os.environ.get('DISPLAY'))


class TkWindow:
    """One Tk window showing ``store``'s frames; reports to ``status``."""

    def __init__(self, store: FrameStore, status: DisplayStatus, *,
                 on_close: Callable[[], None]) -> None:
        self.store, self.status, self.on_close = store, status, on_close
        self._root: tkinter.Tk | None = None
        self._label: tkinter.Label | None = None
        self._photo: tkinter.PhotoImage | None = None
        self._pending: Frame | None = None
        self._title = ''
        self._visible = True

    def open(self) -> None:
        """Connect to the X display and make the (empty) window.

        :raises WindowError: when Tk cannot open the display.
        """
        try:
            root = tkinter.Tk(className='Eye')
        except tkinter.TclError as error:
            display = os.environ.get('DISPLAY')
            raise WindowError(f'no window on display {display!r}: {error}') from error
        root.geometry('+0+0')
        root.configure(background='black', borderwidth=0, highlightthickness=0)
        root.protocol('WM_DELETE_WINDOW', self.on_close)
        self._photo = tkinter.PhotoImage(master=root, width=1, height=1)
        label = tkinter.Label(root, image=self._photo, borderwidth=0, highlightthickness=0,
                              padx=0, pady=0, background='black')
        label.pack(padx=0, pady=0)
        label.bind('<Button-1>', self._clicked)
        root.bind('<Key>', self._key)
        self._root, self._label = root, label
        self._apply_settings()
        root.update()

    def _apply_settings(self) -> None:
        assert self._root is not None
        settings = self.store.settings
        if settings.title != self._title:
            self._title = settings.title
            self._root.title(settings.title)
        if settings.visible != self._visible:
            self._visible = settings.visible
            if settings.visible:
                self._root.deiconify()
            else:
                self._root.withdraw()

    def _clicked(self, event: tkinter.Event) -> None:
        scale = self.store.settings.scale
        self.status.click(int(event.x / scale), int(event.y / scale))

    def _key(self, event: tkinter.Event) -> None:
        self.status.key(int(event.keysym_num))

    def show(self, frame: Frame) -> None:
        """Draw ``frame`` at the next :meth:`pump`."""
        self._pending = frame

    def pump(self) -> None:
        """Apply settings, draw the pending frame and process Tk's events; never blocks."""
        if self._root is None:
            return
        self._apply_settings()
        frame, self._pending = self._pending, None
        if frame is not None and self._visible and self._photo is not None:
            self._photo.configure(data=ppm(frame.rgb), format='PPM', width=frame.width,
                                  height=frame.height)
        try:
            self._root.update()
        except tkinter.TclError:            # the window was destroyed under us
            self._root = None
            self.on_close()
            return
        if frame is not None and self._visible:
            self.status.shown(frame.index)

    def close(self) -> None:
        """Destroy the window; idempotent."""
        root, self._root = self._root, None
        if root is not None:
            try:
                root.destroy()
            except tkinter.TclError:
                pass
