"""What ``ros2 param list/get/set/dump`` do, through rclpy's own parameter client.

ros2cli is not on PyPI, so the tests of a pip-only install do with rclpy's
:class:`~rclpy.parameter_client.AsyncParameterClient` what a user does with ``ros2 param``; the
dump is written in ``ros2 param dump``'s layout (names split at dots into nested keys), which
``--ros-args --params-file`` reads.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import rclpy
import yaml
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.parameter import Parameter, parameter_value_to_python
from rclpy.parameter_client import AsyncParameterClient

SERVICE_WAIT_S = 60.0
CALL_WAIT_S = 30.0
#: A request not answered within this is sent again.  Services found ready by their client can
#: still drop an answer on a loaded machine: the server's reply writer may not have matched this
#: client's reply reader yet (discovery runs both ways, not at once), and the server gives up on
#: the reply after a short wait.  Every request here is idempotent (list, get, describe, and a
#: set of one value), so sending it again is safe; any of the copies' answers is the answer.
RESEND_S = 1.0


class ParameterTool:
    """A parameter client of one remote node, in a context of its own."""

    def __init__(self, node_name: str) -> None:
        """A client of ``node_name``'s parameter services, waiting (at most
        :data:`SERVICE_WAIT_S`) until they are there.

        :param node_name: the remote node's full name; a leading ``/`` is added when missing.
        :raises AssertionError: when the services do not come in time.
        """
        self.node_name = node_name if node_name.startswith('/') else '/' + node_name
        self.context = Context()
        rclpy.init(context=self.context)
        self.node = rclpy.create_node('parameter_tool', context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.client = AsyncParameterClient(self.node, self.node_name)
        if not self.client.wait_for_services(SERVICE_WAIT_S):
            self.close()
            raise AssertionError(f'{self.node_name} serves no parameters within {SERVICE_WAIT_S} s')

    def _call(self, send: Callable[[], Any]) -> Any:
        """The answer to the request ``send()`` makes (a future), sent again every
        :data:`RESEND_S` while no copy has been answered, for at most :data:`CALL_WAIT_S`."""
        deadline = time.monotonic() + CALL_WAIT_S
        sent: list[Any] = []
        while True:
            sent.append(send())
            resend = min(deadline, time.monotonic() + RESEND_S)
            while time.monotonic() < resend:
                self.executor.spin_once(timeout_sec=max(0.0, resend - time.monotonic()))
                answered = [future for future in sent if future.done()]
                if answered:
                    for future in sent:
                        future.cancel()
                    return answered[0].result()
            if time.monotonic() >= deadline:
                raise AssertionError(f'{self.node_name}: no parameter service answer to '
                                     f'{len(sent)} requests in {CALL_WAIT_S} s')

    def names(self) -> list[str]:
        """``ros2 param list``."""
        return sorted(self._call(self.client.list_parameters).result.names)

    def get(self, *names: str) -> list[Any]:
        """``ros2 param get``: the values as Python values."""
        return [parameter_value_to_python(v)
                for v in self._call(lambda: self.client.get_parameters(list(names))).values]

    def describe(self, name: str) -> Any:
        """``ros2 param describe``: the ParameterDescriptor.

        :param name: the parameter's name.
        """
        return self._call(lambda: self.client.describe_parameters([name])).descriptors[0]

    def set(self, name: str, value: Any) -> tuple[bool, str]:
        """``ros2 param set``: (whether it was taken, the node's reason if not).

        :param name: the parameter's name.
        :param value: the new value, a Python value of the parameter's type.
        """
        result = self._call(
            lambda: self.client.set_parameters([Parameter(name, value=value)])).results[0]
        return result.successful, result.reason

    def dump(self) -> str:
        """``ros2 param dump``: YAML for ``--params-file``."""
        names = self.names()
        tree: dict[str, Any] = {}
        for name, value in zip(names, self.get(*names)):
            *path, leaf = name.split('.')
            branch = tree
            for key in path:
                branch = branch.setdefault(key, {})
            branch[leaf] = value
        return yaml.safe_dump({self.node_name: {'ros__parameters': tree}})

    def close(self) -> None:
        self.executor.shutdown()
        self.node.destroy_node()
        self.context.try_shutdown()
