"""Quality of service of the three channels (docs/design.md: Topics and QoS).

- info: reliable, transient-local, depth 1 — a consumer that starts late gets the current info;
  in queue mode as deep as the data's, so that a burst of info events reaches a queue-mode
  consumer whole (a late queue-mode consumer then also gets up to that many past events).
- data and request: reliable, volatile; depth 1 in latest mode, :data:`QUEUE_CAPACITY` in queue
  mode, so that a consumer up to that many events behind loses none (CARMEN's cap of 1000).
"""

from __future__ import annotations

from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

#: Events a queue-mode consumer may fall behind without loss (CARMEN's cap).
QUEUE_CAPACITY = 1000


def info_qos(queue_mode: bool = False) -> QoSProfile:
    """QoS of info channels.

    :param queue_mode: depth :data:`QUEUE_CAPACITY` rather than 1.
    """
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=QUEUE_CAPACITY if queue_mode else 1,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL)


def stream_qos(queue_mode: bool) -> QoSProfile:
    """QoS of data and request channels.

    :param queue_mode: depth :data:`QUEUE_CAPACITY` rather than 1.
    """
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=QUEUE_CAPACITY if queue_mode else 1,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.VOLATILE)
