"""Hand out ROS domain ids that no other process on this machine holds.

Each claim is an exclusive ``flock`` on ``<lock dir>/<id>.lock``; the lock dies with the process
that holds it, so a crashed test never leaks its domain.  Ids 1-101 are valid on Linux; the ids the
README's shells use by default (42 for ``env.sh``, 57 for ``make demo``) are never handed out.
"""

from __future__ import annotations

import fcntl
import itertools
import os
import pathlib
import tempfile

_FIRST, _LAST = 1, 101
_RESERVED = frozenset({42, 57})
_counter = itertools.count()


class DomainClaim:
    """A held domain id; :meth:`release` (or garbage collection) frees it."""

    def __init__(self, domain_id: int, fd: int) -> None:
        """Made by :func:`claim_domain_id`.

        :param domain_id: the id held.
        :param fd: the open lock file whose ``flock`` holds it; closed on release.
        """
        self.domain_id = domain_id
        self._fd: int | None = fd

    def release(self) -> None:
        """Free the id; idempotent."""
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None

    def __del__(self) -> None:
        self.release()


def _lock_dir() -> pathlib.Path:
    path = pathlib.Path(tempfile.gettempdir()) / f'wurde-ros-domains-{os.getuid()}'
    path.mkdir(mode=0o700, exist_ok=True)
    return path


def claim_domain_id() -> DomainClaim:
    """Claim a free domain id.

    Starts at a different id for each claim (pid and a counter), so that consecutive tests do not
    reuse the domain whose participants may still be leaving.

    :raises RuntimeError: when every id is taken.
    """
    ids = [i for i in range(_FIRST, _LAST + 1) if i not in _RESERVED]
    start = (os.getpid() * 7 + next(_counter) * 13) % len(ids)
    directory = _lock_dir()
    for offset in range(len(ids)):
        domain_id = ids[(start + offset) % len(ids)]
        fd = os.open(directory / f'{domain_id}.lock', os.O_CREAT | os.O_RDWR, 0o600)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            continue
        return DomainClaim(domain_id, fd)
    raise RuntimeError(f'no free ROS domain id in {_FIRST}-{_LAST}')
