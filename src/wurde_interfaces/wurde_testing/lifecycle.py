"""What ``ros2 lifecycle get/set`` do, through rclpy's service clients, safe against lost replies.

ros2cli is not on PyPI (see :mod:`wurde_testing.parameters`).  A service its client finds ready
can still drop a reply on a loaded machine: the server's reply writer may not have matched the
client's reply reader yet (discovery runs both ways, not at once).  GetState is idempotent and is
simply sent again.  ChangeState is not: a second copy of a transition that was taken is refused.
So a transition that gets no answer asks GetState where the node is, and sends the transition
again only while the node is still in the state it started from.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

from lifecycle_msgs.msg import Transition
from lifecycle_msgs.srv import ChangeState, GetState

#: A request not answered within this is looked after (sent again, or the state asked for).
RESEND_S = 1.0
#: The longest single spin, so that the caller's ``spin`` can take its own data meanwhile.
SPIN_S = 0.05

#: ``spin(timeout)``: run the client node's callbacks for at most ``timeout`` seconds.
Spin = Callable[[float], None]


def _ready(spin: Spin, client: Any, deadline: float) -> None:
    while not client.service_is_ready():
        if time.monotonic() > deadline:
            raise AssertionError(f'{client.srv_name}: no service')
        spin(SPIN_S)


def _spin_until(spin: Spin, done: Callable[[], bool], until: float) -> bool:
    while not done():
        if time.monotonic() >= until:
            return False
        spin(max(0.0, min(SPIN_S, until - time.monotonic())))
    return True


def get_state(spin: Spin, get: Any, timeout: float = 30.0) -> str:
    """The node's lifecycle state's label (``'active'``); the request is sent again every
    :data:`RESEND_S` while no copy is answered.

    :param spin: runs the client node's callbacks for at most the seconds given.
    :param get: the node's GetState client.
    :param timeout: the longest wait for the service and an answer, in seconds.
    :raises AssertionError: when there is no service or no answer in time.
    """
    deadline = time.monotonic() + timeout
    _ready(spin, get, deadline)
    sent: list[Any] = []
    while True:
        sent.append(get.call_async(GetState.Request()))
        if _spin_until(spin, lambda: any(f.done() for f in sent),
                       min(deadline, time.monotonic() + RESEND_S)):
            answer = next(f for f in sent if f.done()).result()
            for future in sent:
                future.cancel()
            return str(answer.current_state.label)
        if time.monotonic() >= deadline:
            raise AssertionError(f'{get.srv_name}: no answer to {len(sent)} requests in {timeout} s')


def change_state(spin: Spin, change: Any, get: Any, transition_id: int, goal: str,
                 timeout: float = 30.0) -> bool:
    """Ask for one transition through ChangeState client ``change``; whether the node took it
    and is in state ``goal`` (a label: 'inactive', 'active', 'unconfigured', ...).

    A refused transition (an answer saying so, with the node not at ``goal``) is False; a node
    that neither answers nor reaches ``goal`` within ``timeout`` is an AssertionError.

    :param spin: runs the client node's callbacks for at most the seconds given.
    :param change: the node's ChangeState client.
    :param get: the node's GetState client.
    :param transition_id: a ``lifecycle_msgs/Transition`` id (``Transition.TRANSITION_CONFIGURE``).
    :param goal: the label of the state the transition leads to.
    :param timeout: the longest wait in all, in seconds.
    """
    deadline = time.monotonic() + timeout
    _ready(spin, change, deadline)
    start = get_state(spin, get, max(0.0, deadline - time.monotonic()))
    request = ChangeState.Request(transition=Transition(id=transition_id))
    sent: list[Any] = []
    label = start
    while True:
        if label == start and not any(f.done() for f in sent):
            sent.append(change.call_async(request))
        if _spin_until(spin, lambda: any(f.done() and f.result().success for f in sent),
                       min(deadline, time.monotonic() + RESEND_S)):
            return True
        label = get_state(spin, get, max(0.0, deadline - time.monotonic()))
        if label == goal:
            return True
        if all(f.done() for f in sent):
            return False
        if time.monotonic() >= deadline:
            raise AssertionError(f'{change.srv_name}: transition {transition_id} from {start!r} '
                                 f'neither answered nor reached {goal!r} in {timeout} s '
                                 f'(the node is {label!r})')
