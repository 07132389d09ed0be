"""wurde_testing.lifecycle against a lifecycle server that loses replies, over real DDS.

The server here takes its requests by hand (as rclpy's executor does) and can leave a reply
unsent or a request unhandled for a while: what a loaded machine does to a reply whose writer
has not matched the client's reader yet.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest
import rclpy
from lifecycle_msgs.msg import State, Transition
from lifecycle_msgs.srv import ChangeState, GetState
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor

from wurde_testing.lifecycle import RESEND_S, change_state, get_state

#: (transition, from) → to, the part of the lifecycle state machine these tests walk.
MOVES = {(Transition.TRANSITION_CONFIGURE, 'unconfigured'): 'inactive',
         (Transition.TRANSITION_ACTIVATE, 'inactive'): 'active'}


class LossyLifecycle:
    """GetState and ChangeState of node ``/lossy``: the first ``lose_gets`` GetState replies and
    ``lose_changes`` ChangeState replies are not sent (the transition is still taken), and
    ChangeState requests wait until ``hold_for`` of them have arrived before any is handled."""

    def __init__(self, lose_gets: int = 0, lose_changes: int = 0, hold_for: int = 1) -> None:
        self.context = Context()
        rclpy.init(context=self.context)
        self.node = rclpy.create_node('lossy', context=self.context)
        self.get = self.node.create_service(GetState, '/lossy/get_state', lambda *_: None)
        self.change = self.node.create_service(ChangeState, '/lossy/change_state', lambda *_: None)
        self.label = 'unconfigured'
        self.lose = {self.get: lose_gets, self.change: lose_changes}
        self.hold_for = hold_for
        self.changes = 0
        self.held: list[tuple[Any, Any]] = []
        self.taken: list[int] = []
        self.refused: list[int] = []

    def poll(self) -> None:
        for service in (self.get, self.change):
            with service.handle:
                taken = service.handle.service_take_request(service.srv_type.Request)
            if taken and taken[1] is not None:
                self.held.append((service, taken))
                self.changes += service is self.change
        due = [h for h in self.held if h[0] is self.get or self.changes >= self.hold_for]
        self.held = [h for h in self.held if h not in due]
        for service, (request, header) in due:
            response = self._answer(request)
            if self.lose[service] > 0:
                self.lose[service] -= 1
            else:
                service.send_response(response, header)

    def _answer(self, request: Any) -> Any:
        if isinstance(request, GetState.Request):
            return GetState.Response(current_state=State(label=self.label))
        move = MOVES.get((request.transition.id, self.label))
        if move is None:
            self.refused.append(request.transition.id)
            return ChangeState.Response(success=False)
        self.taken.append(request.transition.id)
        self.label = move
        return ChangeState.Response(success=True)

    def close(self) -> None:
        self.node.destroy_node()
        self.context.try_shutdown()


class Client:
    """The lifecycle clients of ``/lossy`` in a context of their own; ``spin`` also runs the
    server's turn."""

    def __init__(self, server: LossyLifecycle) -> None:
        self.server = server
        self.context = Context()
        rclpy.init(context=self.context)
        self.node = rclpy.create_node('lifecycle_client', context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.change = self.node.create_client(ChangeState, '/lossy/change_state')
        self.get = self.node.create_client(GetState, '/lossy/get_state')

    def spin(self, timeout: float) -> None:
        self.executor.spin_once(timeout_sec=timeout)
        self.server.poll()

    def close(self) -> None:
        self.executor.shutdown()
        self.node.destroy_node()
        self.context.try_shutdown()


@pytest.fixture
def lossy(ros_domain: int, request: pytest.FixtureRequest) -> Iterator[tuple[LossyLifecycle, Client]]:
    server = LossyLifecycle(**getattr(request, 'param', {}))
    client = Client(server)
    try:
        yield server, client
    finally:
        client.close()
        server.close()


@pytest.mark.parametrize('lossy', [{'lose_gets': 2, 'lose_changes': 1}], indirect=True)
def test_a_lost_reply_of_a_taken_transition_is_not_sent_again(lossy) -> None:
    server, client = lossy
    assert change_state(client.spin, client.change, client.get, Transition.TRANSITION_CONFIGURE,
                        'inactive')
    assert server.taken == [Transition.TRANSITION_CONFIGURE] and server.refused == []
    assert get_state(client.spin, client.get) == 'inactive'


@pytest.mark.parametrize('lossy', [{'hold_for': 2}], indirect=True)
def test_a_transition_still_queued_is_sent_again_and_its_copy_refused(lossy) -> None:
    server, client = lossy
    assert change_state(client.spin, client.change, client.get, Transition.TRANSITION_CONFIGURE,
                        'inactive')
    # the first waited for its copy: the first is taken, the copy is refused
    assert server.taken == [Transition.TRANSITION_CONFIGURE] and len(server.refused) >= 1
    assert server.label == 'inactive'


def test_a_refused_transition_is_false(lossy) -> None:
    server, client = lossy
    assert not change_state(client.spin, client.change, client.get, Transition.TRANSITION_ACTIVATE,
                            'active')
    assert server.taken == [] and server.refused == [Transition.TRANSITION_ACTIVATE]
    assert change_state(client.spin, client.change, client.get, Transition.TRANSITION_CONFIGURE,
                        'inactive')
    assert change_state(client.spin, client.change, client.get, Transition.TRANSITION_ACTIVATE,
                        'active')


@pytest.mark.parametrize('lossy', [{'lose_changes': 1000}], indirect=True)
def test_a_transition_that_neither_answers_nor_moves_times_out(lossy) -> None:
    server, client = lossy
    server.label = 'broken'                  # no move from here: every copy is refused, unsent
    assert get_state(client.spin, client.get) == 'broken'     # found, and answering
    with pytest.raises(AssertionError, match='/lossy/'):
        change_state(client.spin, client.change, client.get, Transition.TRANSITION_CONFIGURE,
                     'inactive', timeout=3 * RESEND_S)
    assert server.taken == [] and len(server.refused) >= 1
