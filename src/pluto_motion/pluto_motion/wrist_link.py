"""The motionModule's hold on the wrist (Pluto 8.3): commands on the wrist's ActuatorState stream,
position (pan, tilt) with velocity and acceleration both > 0 ("One must set both the velocity and
acceleration > 0 if you want the position to change").

Nothing is sent while no wrist's reader is matched: a robot without a wrist moves as before.  An
aim is sent when it changes by more than :data:`CHANGE_RAD`, and again every :data:`RESEND_S` until
the wrist's info (the command it executes) shows it: a request published before discovery matched
both ways is lost.  When the motionModule stops aiming, the wrist is brought back to rest (0, 0)
once and left to the user.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

from wurde_core import CommsManager

from .active_scan import Aim
from .wrist_proxy import WristProxy

__all__ = ['CHANGE_RAD', 'MAX_RESENDS', 'RESEND_S', 'WristLink']

#: An aim this close to the one sent is not sent again (rad).
CHANGE_RAD = 0.05
#: Seconds between sends of an aim the wrist has not taken yet.
RESEND_S = 1.0
#: Most resends of the rest position (the user may have commanded the wrist meanwhile).
MAX_RESENDS = 3
REST = Aim(0.0, 0.0, 'at rest: the wrist is the user\'s')


class WristLink:
    """Aims the wrist on stream ``name`` through its :class:`~pluto_motion.wrist_proxy.WristProxy`
    (what to send and when is this class's; how, the proxy's)."""

    def __init__(self, manager: CommsManager, name: str, *, speed: float = 1.0, accel: float = 2.0,
                 log: Callable[[str], object] = print, trace: Callable[[str], object] = lambda text: None) -> None:
        """:param log: says once that the wrist was found; ``trace``: each new aim (often: debug)."""
        self.name, self.speed, self.accel, self.log, self.trace = name, speed, accel, log, trace
        self.proxy = WristProxy(manager, name)
        #: The aim sent last (None: not aiming) and when.
        self.sent: Aim | None = None
        self.sent_at = -math.inf
        self.resends = 0
        self._heard = False

    @property
    def present(self) -> bool:
        """Whether a wrist listens on the stream."""
        present = bool(self.proxy.wrist.peers('request'))
        if present and not self._heard:
            self._heard = True
            self.log(f'wrist {self.name} found: active scanning on')
        return present

    def _taken(self, aim: Aim) -> bool:
        self.proxy.update()
        target = self.proxy.target
        return target is not None and abs(target[0] - aim.pan) < CHANGE_RAD and abs(target[1] - aim.tilt) < CHANGE_RAD

    def update(self, aim: Aim | None, now: float | None = None) -> None:
        """Aim the wrist at ``aim``; None: rest once, then leave it."""
        now = time.monotonic() if now is None else now
        if not self.present:
            return
        if aim is None:
            if self.sent is None:
                return
            if self.sent is REST:
                if self._taken(REST) or self.resends >= MAX_RESENDS:
                    self.sent = None                       # at rest: the user's again
                    return
                if now - self.sent_at < RESEND_S:
                    return
                self.resends += 1
            aim = REST
        elif self.sent is not None and abs(aim.pan - self.sent.pan) < CHANGE_RAD and \
                abs(aim.tilt - self.sent.tilt) < CHANGE_RAD:
            if self._taken(self.sent) or now - self.sent_at < RESEND_S:
                return
            aim = self.sent
        else:
            self.resends = 0
        if self.sent is None or aim.why != self.sent.why:
            self.trace(f'wrist: {aim.why} (pan {aim.pan:.2f}, tilt {aim.tilt:.2f} rad)')
        self.proxy.move(aim.pan, aim.tilt, self.speed, self.accel)
        self.sent, self.sent_at = aim, now
