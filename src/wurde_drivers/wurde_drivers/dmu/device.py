"""The Crossbow DMU driver over a :class:`SerialLink`: handshake, streaming, robot-frame samples.

Pluto's DMUraw_state (Pluto Software Documentation 8.2) is "the data off the crossbow inertial
sensor with the z axis changed to point up (x forwards and y to the left)". The sensor's frame is
x forward, y right, z down; turning z up while keeping x is a rotation of pi about x, so y and z
of every vector change sign. Angular rates are vectors too, so rate_y and rate_z change sign;
roll (about x) keeps its sign and pitch (about y) changes it (nose-up pitch is positive about
y-right, negative about y-left). :func:`to_robot_frame` does exactly that.

Life cycle: construct (no I/O) -> :meth:`DmuDriver.connect` (may raise) -> :meth:`DmuDriver.poll`
in a loop (never blocks longer than asked, never raises on bad bytes) -> :meth:`DmuDriver.close`.
A unit that falls silent (unplugged, power cycled into polled mode) is re-armed from ``poll``:
after ``rearm_after`` seconds of silence the driver sends the mode and continuous commands again,
without waiting for an answer, every ``rearm_after`` seconds until packets flow.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable

from ..errors import DeviceTimeout
from ..ports.serial_link import LinkStats, SerialLink
from . import codec
from .sample import Inertial

__all__ = ['DmuDriver', 'RawSample', 'to_robot_frame']


@dataclasses.dataclass(frozen=True, kw_only=True)
class RawSample(Inertial):
    """One DMU packet in the robot frame (x forward, y left, z up): Pluto's DMUraw_state.

    The :class:`~.sample.Inertial` fields (+g along z at rest), then ``stamp`` the driver clock
    when it was sent (the read's time, an earlier packet of the same read back by the unit's time
    word), ``temperature`` in degC and ``time_ticks`` the sensor's raw 16-bit counter.
    """

    stamp: float
    temperature: float
    time_ticks: int


def to_robot_frame(packet: codec.DmuPacket, stamp: float) -> RawSample:
    """``packet`` (sensor frame, z down) as a :class:`RawSample` (robot frame, z up).

    :param packet: a decoded packet.
    :param stamp: when the unit sent it, on the driver's clock (s).
    """
    return RawSample(
        stamp=stamp, roll=packet.roll,
        pitch=None if packet.pitch is None else -packet.pitch,
        rate_x=packet.rate_x, rate_y=-packet.rate_y, rate_z=-packet.rate_z,
        accel_x=packet.accel_x, accel_y=-packet.accel_y, accel_z=-packet.accel_z,
        temperature=packet.temperature, time_ticks=packet.time_ticks)


class DmuDriver:
    """Talks to one DMU on a serial link; see the module docstring for the life cycle."""

    def __init__(self, link: SerialLink, *, mode: codec.DmuMode = codec.DmuMode.ANGLE,
                 scale: codec.DmuScale = codec.DmuScale(), rearm_after: float = 1.0,
                 clock: Callable[[], float] = time.monotonic) -> None:
        """Keep the settings; no I/O until :meth:`connect`.

        :param link: the serial port (opened by :meth:`connect`; the link reopens a vanished port).
        :param mode: angle mode (roll and pitch from the sensor's filter) or scaled mode.
        :param scale: the unit's ranges.
        :param rearm_after: seconds of silence after which ``poll`` re-sends mode and continuous.
        :param clock: the time source for :attr:`RawSample.stamp` and :attr:`silent_for`.
        """
        self.link = link
        self.mode = mode
        self.scale = scale
        self.rearm_after = rearm_after
        self._clock = clock
        self._deframer = codec.DmuDeframer(mode, scale)
        self._counted = (0, 0)
        self._last_packet = clock()
        self._last_stamp = -float('inf')      # the stamp of the last packet handed out
        self._next_rearm = float('inf')
        #: Times ``poll`` re-sent the start commands to a silent unit.
        self.rearms = 0

    # -- status -------------------------------------------------------------------------------
    @property
    def stats(self) -> LinkStats:
        """Bytes, packets (``telegrams``), ``bad_crc`` (checksum), ``bytes_skipped``, timeouts,
        disconnects and reconnects of the link."""
        return self.link.stats

    @property
    def silent_for(self) -> float:
        """Seconds since the last good packet (or since :meth:`connect`)."""
        return self._clock() - self._last_packet

    # -- life cycle ---------------------------------------------------------------------------
    def connect(self, timeout: float = 2.0) -> None:
        """Open the port, stop any stream, ping, set the mode and start continuous mode.

        :param timeout: seconds for the whole handshake.
        :raises DeviceError: the port cannot be opened.
        :raises DeviceTimeout: the unit does not answer the ping or the mode command in time.
        """
        deadline = time.monotonic() + timeout
        self.link.open()
        self.link.write(codec.CMD_POLLED)
        self._drain(min(0.1, timeout / 4), deadline)
        self.link.reset_input()
        self._deframer.reset()
        self._expect(codec.CMD_PING, codec.REPLY_PING, deadline)
        self._expect(self.mode.command, self.mode.reply, deadline)
        self.link.write(codec.CMD_CONTINUOUS)
        self._last_packet = self._clock()
        self._next_rearm = self._last_packet + self.rearm_after

    def reconnect(self, timeout: float = 2.0) -> None:
        """Close the port and :meth:`connect` again (same errors).

        :param timeout: seconds for the handshake.
        """
        self.link.close()
        self.connect(timeout)

    def close(self) -> None:
        """Stop the stream (best effort) and close the port; idempotent."""
        if self.link.is_open:
            self.link.write(codec.CMD_POLLED)
        self.link.close()
        self._next_rearm = float('inf')

    def _drain(self, quiet: float, deadline: float) -> None:
        """Read until the line has been quiet for ``quiet`` seconds (or the deadline)."""
        while time.monotonic() < deadline:
            if not self.link.read(min(quiet, max(0.0, deadline - time.monotonic()))):
                return

    def _expect(self, command: bytes, reply: bytes, deadline: float) -> None:
        self.link.write(command)
        while True:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                self.link.stats.timeouts += 1
                raise DeviceTimeout(f'{self.link.url}: DMU did not answer {command!r} with '
                                    f'{reply!r}')
            if reply in self.link.read(remaining):
                return

    # -- streaming ----------------------------------------------------------------------------
    def poll(self, timeout: float) -> list[RawSample]:
        """Packets that arrive within ``timeout`` seconds, in the robot frame.

        Bad checksums and skipped bytes are counted in :attr:`stats`; a silent unit is re-armed (see
        the module docstring).

        :param timeout: the longest wait in seconds.
        :returns: as soon as at least one packet has been decoded, every sample received so far;
            an empty list at the deadline.
        """
        deadline = time.monotonic() + timeout
        samples: list[RawSample] = []
        while True:
            self._maybe_rearm()
            remaining = max(0.0, deadline - time.monotonic())
            data = self.link.read(remaining)
            if data:
                samples += self._feed(data)
            if samples or time.monotonic() >= deadline:
                break
            if not data and not self.link.is_open:
                # the port vanished: the link reopens it later; do not spin until the deadline
                time.sleep(min(0.01, max(0.0, deadline - time.monotonic())))
        if not samples and timeout > 0:
            self.link.stats.timeouts += 1
        return samples

    def _feed(self, data: bytes) -> list[RawSample]:
        packets = self._deframer.feed(data)
        stats = self.link.stats
        bad, skipped = self._deframer.bad_checksum, self._deframer.bytes_skipped
        stats.bad_crc += bad - self._counted[0]
        stats.bytes_skipped += skipped - self._counted[1]
        self._counted = (bad, skipped)
        if not packets:
            return []
        stats.telegrams += len(packets)
        now = self._clock()
        self._last_packet = now
        self._next_rearm = now + self.rearm_after
        stamps = self._stamps(packets, now)
        return [to_robot_frame(packet, stamp) for packet, stamp in zip(packets, stamps)]

    def _stamps(self, packets: list[codec.DmuPacket], now: float) -> list[float]:
        """When each packet of one read was sent: the last one now, each earlier one back by the
        unit's own time word (:data:`codec.TIME_TICK_S` a count; it wraps every 52 ms, longer
        than a streaming unit's packet period), never before the previous read's last.

        A loaded machine reads a burst of packets at once; stamped all alike, the heading filter
        would see no time pass between them (and a first burst would leave the heading at 0).
        """
        stamps = [now]
        for later, earlier in zip(reversed(packets), list(reversed(packets))[1:]):
            stamps.append(stamps[-1] - ((later.time_ticks - earlier.time_ticks) & 0xFFFF) * codec.TIME_TICK_S)
        stamps.reverse()
        floor = self._last_stamp
        out = []
        for stamp in stamps:
            floor = max(floor, stamp)
            out.append(floor)
        self._last_stamp = now
        return out

    def _maybe_rearm(self) -> None:
        now = self._clock()
        if now < self._next_rearm:
            return
        self._next_rearm = now + self.rearm_after
        if self.link.write(self.mode.command + codec.CMD_CONTINUOUS):
            self.rearms += 1
