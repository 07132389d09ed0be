"""A base's sensors as standard messages: sonar and bumpers (``sensor_msgs/Range``) and the
battery (``sensor_msgs/BatteryState``); topic names from :func:`wurde_drivers.ros_std.std_topic`.

**Sonar: one topic, one frame per transducer** (``/N/sonar``, frame ``<N>Sonar_i``). A ring of
16 to 48 transducers as one topic each would be 48 publishers per base (discovery traffic, and a
subscriber per topic for every client), while everything that reads ``Range`` places a reading
by its ``header.frame_id`` (RViz's Range display with a buffer length of the ring's size, Nav2's
range sensor layer); a ring fires as a set anyway, so one topic carries one message per
transducer, each in its own frame.

**Bumpers: ``sensor_msgs/Range`` as a fixed-distance ranger** (``/N/bumpers``, frame
``<N>Bumpers_i``). common_interfaces has no contact message; Range documents exactly the binary
case: "Fixed distance rangers require min_range == max_range; -Inf represents a detection within
fixed distance, +Inf represents no detection within the fixed distance". A bumper is such a ranger
with distance 0: pressed is ``-inf``, free ``+inf``. So RViz shows which one is pressed where, and
a costmap's range layer can mark it, with no custom message type. (``radiation_type`` knows only
ULTRASOUND and INFRARED; a switch is neither, so it stays at the default, which fixed-distance
consumers do not read.)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from sensor_msgs.msg import BatteryState, Range
from wurde_core.ros_messages import set_stamp

from .ros_std import std_topic, watched
from .ros_std_frames import BASE_FRAME, member_frame

__all__ = ['BatteryPublisher', 'BumperPublisher', 'SonarPublisher']

_DEPTH = 10
#: A whole ring in the queue (the B21r has 48 sonars), so a burst loses none.
_RING_DEPTH = 64


def _range_messages(stream: str, count: int, *, field_of_view: float, min_range: float,
                    max_range: float, radiation: int) -> list[Range]:
    messages = []
    for i in range(count):
        msg = Range()
        msg.header.frame_id = member_frame(stream, i)
        msg.radiation_type = radiation
        msg.field_of_view = float(field_of_view)
        msg.min_range, msg.max_range = float(min_range), float(max_range)
        messages.append(msg)
    return messages


class SonarPublisher:
    """``/N/sonar``: one ``Range`` per transducer, in its frame ``<sonar stream>_i``.

    Call :meth:`configure` with the ring's info (count, half angle, max range), then
    :meth:`publish` with each reading set; readings before the first configure are dropped.
    """

    def __init__(self, node: Any, base: str, stream: str) -> None:
        self.publisher = node.create_publisher(Range, std_topic(base, 'sonar'), _RING_DEPTH)
        self.stream = stream
        self.messages: list[Range] = []

    def configure(self, *, count: int, half_angle: float, max_range: float) -> None:
        """The cone is twice the half angle; the RangeFinder info gives no minimum range: 0."""
        self.messages = _range_messages(self.stream, count, field_of_view=2 * half_angle, min_range=0.0,
                                        max_range=max_range, radiation=Range.ULTRASOUND)

    def publish(self, ranges: Sequence[float], stamp: float) -> None:
        if not watched(self.publisher):
            return
        for msg, value in zip(self.messages, ranges):
            set_stamp(msg, stamp)
            msg.range = float(value)
            self.publisher.publish(msg)


class BumperPublisher:
    """``/N/bumpers``: one fixed-distance ``Range`` per bumper (pressed ``-inf``, free ``+inf``)."""

    def __init__(self, node: Any, base: str, stream: str) -> None:
        self.publisher = node.create_publisher(Range, std_topic(base, 'bumpers'), _RING_DEPTH)
        self.stream = stream
        self.messages: list[Range] = []

    def configure(self, count: int) -> None:
        """``count`` bumpers around the robot, each covering an equal share of the turn (the
        Bumper info gives positions only)."""
        self.messages = _range_messages(self.stream, count, field_of_view=2 * math.pi / max(1, count),
                                        min_range=0.0, max_range=0.0, radiation=Range.ULTRASOUND)

    def publish(self, pressed: Sequence[bool], stamp: float) -> None:
        if not watched(self.publisher):
            return
        for msg, down in zip(self.messages, pressed):
            set_stamp(msg, stamp)
            msg.range = -math.inf if down else math.inf
            self.publisher.publish(msg)


class BatteryPublisher:
    """``/N/battery``: the Power stream as ``sensor_msgs/BatteryState`` (frame ``base_link``).

    Units converted to the message's: current positive when charging (the Power stream's is
    positive when discharging), charge and capacity in Ah (from joules at the nominal voltage),
    percentage 0 to 1. What the Power stream does not know is NaN, as the message asks
    (temperature always; capacity until the info came; current on a base that does not measure
    it, the rFLEX).
    """

    def __init__(self, node: Any, base: str) -> None:
        self.publisher = node.create_publisher(BatteryState, std_topic(base, 'battery'), _DEPTH)
        self.capacity_ah = math.nan

    def configure(self, *, nominal_voltage: float, capacity_j: float) -> None:
        if nominal_voltage > 0 and capacity_j > 0:
            self.capacity_ah = capacity_j / nominal_voltage / 3600.0

    def publish(self, *, voltage: float, current: float, charge: float, charging: bool, stamp: float) -> None:
        if not watched(self.publisher):
            return
        msg = BatteryState()
        set_stamp(msg, stamp)
        msg.header.frame_id = BASE_FRAME
        msg.voltage = float(voltage)
        msg.temperature = math.nan
        msg.current = -float(current)
        msg.percentage = float(charge)
        msg.capacity = msg.design_capacity = float(self.capacity_ah)
        msg.charge = float(charge * self.capacity_ah)
        msg.power_supply_status = (BatteryState.POWER_SUPPLY_STATUS_CHARGING if charging
                                   else BatteryState.POWER_SUPPLY_STATUS_DISCHARGING)
        msg.power_supply_health = BatteryState.POWER_SUPPLY_HEALTH_UNKNOWN
        msg.power_supply_technology = BatteryState.POWER_SUPPLY_TECHNOLOGY_UNKNOWN  # lead-acid: no constant
        msg.present = True
        self.publisher.publish(msg)
