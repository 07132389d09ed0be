"""What every Pluto proxy shares (Pluto 5: "If one needs to communicate with a module one need only
include the proxy file and then create a proxy object ... It then translates simple c++ method
calls into the necessary sequence of corba messages"): the module's streams as consumers of the
program's manager, requests held until the module reads them, and waiting on what arrives with a
deadline.  The chain's proxies (:mod:`.chain_proxy`) and the device and navigation proxies
(``wrist_proxy``, ``base_proxy``, ``slam_proxy`` ...) are built on it.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

from wurde_core import CommsManager, RunState

__all__ = ['Proxy']


class Proxy:
    """A module as seen from ``manager``; subclasses register their streams and read them in
    :meth:`_take`."""

    def __init__(self, manager: CommsManager) -> None:
        """Hold nothing yet; subclasses register their streams with ``manager``.

        :param manager: the program's manager; the proxy's consumers are registered with it and
            :meth:`wait_for` runs its loop.
        """
        self.manager = manager
        #: Objects whose request waits for the module's reader to be matched (see :meth:`_request`).
        self._held: list[Any] = []

    def _consume(self, obj: Any, *, queue_mode: bool = False) -> Any:
        """Register ``obj`` as a consumer of the manager; ``obj``."""
        obj.set_queue_mode(queue_mode)
        self.manager.register_consumer(obj)
        return obj

    def _request(self, obj: Any) -> bool:
        """Publish ``obj``'s request now, or hold it while the module's reader is not matched yet
        (a request channel keeps nothing for a reader that comes later, so a command typed or
        sent before discovery finished would be lost): :meth:`_exchange` publishes the newest
        request of each held object, in the order they were held, once it is.  Whether it went
        now."""
        if obj.peers('request'):
            return obj.publish_request()
        if obj not in self._held:
            self._held.append(obj)
        return False

    def _send_held(self) -> None:
        while self._held and self._held[0].peers('request'):
            self._held.pop(0).publish_request()

    def _take(self) -> None:
        """Take in what arrived on the module's streams (each proxy its own)."""

    def _exchange(self) -> None:
        """Send held requests whose reader is matched now; take in what arrived."""
        self._send_held()
        self._take()

    def update(self) -> object:
        """Send held requests, take in what arrived (the accessors then read it)."""
        self._exchange()
        return None

    def wait_for(self, test: Callable[[Any], bool], timeout: float) -> bool:
        """Run the manager's loop until ``test(self)`` holds; False after ``timeout`` s or on Quit.

        :param test: asked with the proxy after each turn, once what arrived is taken in.
        :param timeout: the longest wait (s).
        """
        deadline = time.monotonic() + timeout
        while True:
            self._exchange()
            if test(self):
                return True
            if time.monotonic() >= deadline or not self.spin_once(0.05):
                return False

    def spin_once(self, timeout: float) -> bool:
        """One turn of the manager's loop, waiting at most ``timeout`` s for something to arrive;
        False when the program is to quit.

        :param timeout: the longest wait (s).
        """
        if self.manager.run_update() != RunState.RUN:
            return False
        self.manager.wait(timeout)
        return True
