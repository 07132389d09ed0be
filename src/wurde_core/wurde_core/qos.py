"""Quality of service of the three channels (DESIGN: Topics and QoS).

- info: reliable, transient-local, depth 1 — a consumer that starts late gets the current info.
- data and request: reliable, volatile; depth 1 in latest mode, :data:`QUEUE_CAPACITY` in queue
  mode, so that a consumer up to that many events behind loses none (CARMEN's cap of 1000).
"""

from __future__ import annotations

from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

#: Events a queue-mode consumer may fall behind without loss (CARMEN's cap).
QUEUE_CAPACITY = 1000


def info_qos() -> QoSProfile:
    """QoS of info channels."""
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL)


def stream_qos(queue_mode: bool) -> QoSProfile:
    """QoS of data and request channels."""
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=QUEUE_CAPACITY if queue_mode else 1,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.VOLATILE)
