"""Two hosts on one machine for the two-host test: network namespaces joined by a veth pair.

Each host is a network namespace of its own with a loopback and one end of a veth pair, on an
address block of the test's choosing (``10.231.<domain>.0/24``); nothing of it touches the
machine's own interfaces.  DDS inside them discovers over that link only: the namespaces have no
other interface, discovery stays LOCALHOST (as everywhere else) and reaches the other host only as
its static peer (``ROS_STATIC_PEERS``, which the range does not restrict), and Fast DDS's
shared-memory transport is off (both namespaces share /dev/shm, which would
let the two "hosts" talk without the link).  Each process also gets a UTS namespace with the
host's own name, so the MCP's table shows where each module runs.  Needs root (``ip netns``).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from collections.abc import Sequence

from wurde_testing import ChildProcess


def can_make_namespaces() -> str | None:
    """Why two hosts cannot be built here, or None when they can."""
    if os.geteuid() != 0:
        return 'network namespaces need root'
    for tool in ('ip', 'unshare'):
        if shutil.which(tool) is None:
            return f'no {tool} command'
    return None


def _ip(*args: str) -> None:
    subprocess.run(['ip', *args], check=True, capture_output=True, text=True, timeout=30)


class Host:
    """One end: a namespace, its veth end and its address."""

    def __init__(self, name: str, namespace: str, device: str, address: str) -> None:
        self.name, self.namespace, self.device, self.address = name, namespace, device, address

    def command(self, argv: Sequence[str]) -> list[str]:
        """``argv`` run inside this host (its network namespace, its host name); the DDS settings
        are :meth:`TwoHosts.env`'s."""
        return ['ip', 'netns', 'exec', self.namespace, 'unshare', '--uts', 'sh', '-c',
                f'hostname {self.name} && exec "$@"',
                'sh', *argv]

    def start(self, argv: Sequence[str], env: dict[str, str]) -> ChildProcess:
        """A Python program (``argv[0]`` a script or entry point) running on this host."""
        return ChildProcess(self.command([sys.executable, *argv]), env=env, python=False)

    def run(self, argv: Sequence[str], env: dict[str, str],
            timeout: float = 120.0) -> subprocess.CompletedProcess[str]:
        return subprocess.run(self.command([sys.executable, *argv]), env=env,
                              capture_output=True, text=True, timeout=timeout)


class TwoHosts:
    """Hosts ``a`` and ``b`` joined by a veth pair; :meth:`close` removes everything."""

    def __init__(self, tag: int, names: tuple[str, str] = ('robot', 'desktop')) -> None:
        suffix = f'{os.getpid() % 100000}{tag % 100}'
        block = f'10.231.{tag % 250}'
        self.a = Host(names[0], f'wurde-a-{suffix}', f'wa{suffix}'[:15], f'{block}.1')
        self.b = Host(names[1], f'wurde-b-{suffix}', f'wb{suffix}'[:15], f'{block}.2')
        self._made: list[str] = []
        try:
            for host in (self.a, self.b):
                _ip('netns', 'add', host.namespace)
                self._made.append(host.namespace)
            _ip('link', 'add', self.a.device, 'type', 'veth', 'peer', 'name', self.b.device)
            for host in (self.a, self.b):
                _ip('link', 'set', host.device, 'netns', host.namespace)
                _ip('-n', host.namespace, 'addr', 'add', f'{host.address}/24', 'dev', host.device)
                _ip('-n', host.namespace, 'link', 'set', 'lo', 'up')
            self.connect()
        except BaseException:
            self.close()
            raise

    def env(self, host: Host, domain: int, **extra: str) -> dict[str, str]:
        """The environment of a process on ``host``, in ``domain``, the other host its static peer.
        Discovery stays LOCALHOST: the other host is reached as the static peer only."""
        peer = self.b if host is self.a else self.a
        return dict(os.environ, ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE='LOCALHOST',
                    ROS_STATIC_PEERS=peer.address, FASTDDS_BUILTIN_TRANSPORTS='UDPv4', **extra)

    def connect(self) -> None:
        """Bring the link up (again), with the multicast route discovery uses."""
        for host in (self.a, self.b):
            _ip('-n', host.namespace, 'link', 'set', host.device, 'up')
            _ip('-n', host.namespace, 'route', 'replace', '224.0.0.0/4', 'dev', host.device)

    def cut(self) -> None:
        """Take host a's end of the link down (``ip link set down``)."""
        _ip('-n', self.a.namespace, 'link', 'set', self.a.device, 'down')

    def close(self) -> None:
        for namespace in reversed(self._made):  # deleting a namespace deletes its veth end
            pids = subprocess.run(['ip', 'netns', 'pids', namespace], capture_output=True,
                                  text=True).stdout.split()
            for pid in pids:  # anything a failed test left running in it
                try:
                    os.kill(int(pid), 9)
                except (ProcessLookupError, ValueError):
                    pass
            subprocess.run(['ip', 'netns', 'del', namespace], capture_output=True)
        self._made.clear()
