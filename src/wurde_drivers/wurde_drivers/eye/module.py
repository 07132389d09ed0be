"""eye: WURDE's Eye (guide 7.8), which "displays images published by the ImagePublisher vision
operator or other ImageSource capability provider".

Streams (module ``Eye``, ``-n`` renames it):

================== ============== ===========================================================
stream / alias     interface      what
================== ============== ===========================================================
``EyeImageClient`` ImageTransport the images shown (consumed, latest only), assigned by the
                                  MCP as in the guide's appendix mapping unless ``-i STREAM``
                                  names the stream
module name        ImageDisplay   supplied: info is the settings (title, stream, visible,
                                  scale, overlay; requests change all but ``stream``, which
                                  is locked to suppliers), data the display's status (frames
                                  shown, display rate, clicks, last key), sent when it changes
                                  (at most every 0.1 s) and every second
================== ============== ===========================================================

Display (``-d``): ``window`` (Tk on ``$DISPLAY``), ``web`` (a page on ``http://127.0.0.1:8090/``,
``-p`` and ``-b`` change port and address), or ``auto`` (default: the window when ``DISPLAY``
is set and Tk opens it, else the page). Both show the same frames (:mod:`.frames`). The four
encodings are decoded by :mod:`wurde_drivers.image_codec`; an image that does not decode is
skipped and logged (once per kind of fault until a good image comes).
"""

from __future__ import annotations

import dataclasses
import math
import sys
import time
from typing import Protocol

from wurde_core import CommsManager, ConnectionStrategy, LockMode, Logger, RunState
from wurde_core.interfaces import ImageDisplay, ImageSource

from ..image_codec import ImageFormatError, decode
from ..module_setup import run_loop, set_loop
from .frames import MAX_SCALE, DisplaySettings, Frame, FrameStore
from .status import DisplayStatus
from .web import DEFAULT_ADDRESS, DEFAULT_PORT, WebDisplay
from .window import TkWindow, WindowError, display_available

__all__ = ['ALIAS', 'Display', 'Eye', 'default_title', 'main', 'open_display']

#: The consumer's alias in MCP mappings (the guide's appendix: ``EyeImageClient``).
ALIAS = 'EyeImageClient'
LOOP_S = 0.02
STATUS_MIN_S, STATUS_MAX_S = 0.1, 1.0
HELP = ('  -i STREAM    the ImageTransport stream to show (default: assigned to EyeImageClient)\n'
        '  -d DISPLAY   window, web or auto (default auto: the window where DISPLAY is set)\n'
        f'  -p PORT      the web page\'s port (default {DEFAULT_PORT}; 0: any free port)\n'
        f'  -b ADDRESS   the web page\'s address (default {DEFAULT_ADDRESS}: this machine only)\n'
        '  -t TITLE     window title (default: Eye: STREAM)\n'
        '  -s SCALE     display scale factor (default 1)')


def default_title(stream: str) -> str:
    """The window's title unless ``-t`` or a request sets one."""
    return f'Eye: {stream}'


class Display(Protocol):
    """What the Eye needs of a display (:class:`TkWindow`, :class:`WebDisplay`)."""

    def show(self, frame: Frame) -> None: ...

    def pump(self) -> None: ...

    def close(self) -> None: ...


class _NoDisplay:
    """Registration mode (``-r``): the module reports and quits without opening anything."""

    def show(self, frame: Frame) -> None:
        pass

    def pump(self) -> None:
        pass

    def close(self) -> None:
        pass


class Eye:
    """The module's work: images in, decoded, composed, shown; settings and status on ImageDisplay."""

    def __init__(self, manager: CommsManager, logger: Logger, source: ImageSource,
                 control: ImageDisplay, store: FrameStore, status: DisplayStatus,
                 display: Display) -> None:
        """Registered objects in; publishes the first info at once."""
        self.manager, self.logger = manager, logger
        self.source, self.control = source, control
        self.store, self.status, self.display = store, status, display
        self.decoded = 0
        self.bad_images = 0
        self._fault = ''
        self._status_version = -1
        self._status_at = -math.inf
        self._info_pending = True
        self._publish_info()

    # -- settings ----------------------------------------------------------------------------------
    def _publish_info(self) -> None:
        settings, info = self.store.settings, self.control.info
        info.title.set_value(settings.title)
        info.stream.set_value(settings.stream)
        info.visible.set_value(settings.visible)
        info.scale.set_value(settings.scale)
        info.overlay.set_value(settings.overlay)
        # Not sent while the module is not running: sent again next turn.
        self._info_pending = not self.control.publish_info()

    def _requests(self) -> None:
        changed = False
        while self.control.get_next_request():
            request = self.control.requests
            fields = set(request.ros_message().set_fields)
            values = {name: getattr(request, name).get_value() for name in fields
                      if name in ('title', 'visible', 'scale', 'overlay')}
            scale = values.get('scale')
            if scale is not None and not (math.isfinite(scale) and 0 < scale <= MAX_SCALE):
                self.logger.warn(f'{self.manager.name}: scale {scale} refused (0 < scale <= '
                                 f'{MAX_SCALE:g})')
                del values['scale']
            if values:
                self.store.set_settings(dataclasses.replace(self.store.settings, **values))
                changed = True
        if changed:
            frame = self.store.latest()
            if frame is not None:
                self.display.show(frame)
            self._publish_info()

    # -- images ------------------------------------------------------------------------------------
    def _take_image(self) -> None:
        if not self.source.get_next_data():
            return
        data = self.source.data
        try:
            rgb = decode(data.width, data.height, data.encoding, data.step, self.source.pixels())
        except ImageFormatError as error:
            self.bad_images += 1
            if str(error) != self._fault:
                self._fault = str(error)
                self.logger.warn(f'{self.manager.name}: image {data.frame_index} from '
                                 f'{data.source or "?"} not shown: {error}')
            return
        if self._fault:
            self._fault = ''
            self.logger.notice(f'{self.manager.name}: images decode again')
        self.decoded += 1
        self.display.show(self.store.put(rgb, data.frame_index))

    def _publish_status(self) -> None:
        now = time.monotonic()
        due = now - self._status_at >= STATUS_MAX_S or (
            self.status.version != self._status_version and now - self._status_at >= STATUS_MIN_S)
        if not due:
            return
        self._status_version = self.status.version
        snapshot, data = self.status.snapshot(), self.control.data
        data.frames_shown = snapshot.frames_shown
        data.display_rate = snapshot.display_rate
        data.click_count = snapshot.click_count
        data.click_x, data.click_y = snapshot.click_x, snapshot.click_y
        data.key = snapshot.key
        if self.control.publish_data():
            self._status_at = now

    def _follow_assignment(self) -> None:
        """Name the stream in the info (and the default title) once the MCP assigned one
        (STRAT_ASSIGNED)."""
        stream, settings = self.source.stream, self.store.settings
        if stream and stream != settings.stream:
            title = default_title(stream) if settings.title == default_title(settings.stream) \
                else settings.title
            self.store.set_settings(dataclasses.replace(settings, stream=stream, title=title))
            self._publish_info()

    def step(self) -> None:
        """One loop turn: requests, the newest image, the display's events, the status."""
        self._follow_assignment()
        if self._info_pending:
            self._publish_info()
        self._requests()
        self._take_image()
        self.display.pump()
        self._publish_status()

    def close(self) -> None:
        self.display.close()
        self.store.close()


def open_display(manager: CommsManager, store: FrameStore, status: DisplayStatus, mode: str, *,
                 address: str = DEFAULT_ADDRESS, port: int = DEFAULT_PORT) -> Display:
    """The display ``mode`` asks for (``window``, ``web``); ``auto`` is the window where
    ``DISPLAY`` is set and Tk opens it, else the page. Opened before the module registers
    anything, so a display that cannot open ends the program before it joins the ROS graph.

    :raises SystemExit: (status 2, the reason on stderr) when the asked display cannot open.
    """
    name, stream = manager.name, store.settings.stream
    if mode == 'window' or (mode == 'auto' and display_available()):
        window = TkWindow(store, status, on_close=lambda: manager.set_state(RunState.QUIT))
        try:
            window.open()
            print(f'eye: {name} shows {stream} in a window', flush=True)
            return window
        except WindowError as error:
            if mode == 'window':
                print(f'eye: {error}', file=sys.stderr, flush=True)
                raise SystemExit(2) from None
            print(f'eye: {error}; showing the web page instead', file=sys.stderr, flush=True)
    web = WebDisplay(store, status, address=address, port=port)
    try:
        web.open()
    except OSError as error:
        print(f'eye: cannot serve on {address}:{port}: {error}', file=sys.stderr, flush=True)
        raise SystemExit(2) from None
    print(f'eye: {name} shows {stream} on {web.url}', flush=True)
    return web


def _number(program: str, option: str, text: str, kind: type) -> float:
    try:
        return kind(text)
    except ValueError:
        print(f'{program}: -{option} {text!r} is not a number', file=sys.stderr, flush=True)
        raise SystemExit(2) from None


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('Eye')
    manager.set_help_string(HELP)
    opts = manager.parse_options(argv, 'i:d:p:b:t:s:')
    user = opts.user
    mode = user.get('d', 'auto')
    if mode not in ('window', 'web', 'auto'):
        print(f'eye: -d {mode!r}: window, web or auto', file=sys.stderr, flush=True)
        return 2
    port = int(_number(argv[0], 'p', user.get('p', str(DEFAULT_PORT)), int))
    scale = _number(argv[0], 's', user.get('s', '1'), float)
    if not (math.isfinite(scale) and 0 < scale <= MAX_SCALE):
        print(f'eye: -s {scale}: 0 < scale <= {MAX_SCALE:g}', file=sys.stderr, flush=True)
        return 2
    stream = user.get('i')
    source = ImageSource(stream) if stream else ImageSource(ConnectionStrategy.ASSIGNED, ALIAS)
    shown = stream or ALIAS
    settings = DisplaySettings(title=user.get('t', default_title(shown)), stream=shown, scale=scale)
    store, status = FrameStore(settings), DisplayStatus()
    display = _NoDisplay() if opts.registration else open_display(
        manager, store, status, mode, address=user.get('b', DEFAULT_ADDRESS), port=port)
    control = ImageDisplay(manager.name)
    control.info.stream.lock(LockMode.SUPPLIERS)
    logger = Logger(manager.name)
    manager.register_consumer(source)
    manager.register_supplier(control)
    manager.register_supplier(logger)
    set_loop(manager, LOOP_S)
    eye = Eye(manager, logger, source, control, store, status, display)
    return run_loop(manager, eye.step, eye.close)


if __name__ == '__main__':
    sys.exit(main())
