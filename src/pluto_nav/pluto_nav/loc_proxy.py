"""LocProxy: Pluto's ``loc_proxy`` for WURDE programs — read the localization's poses, set a pose.

Pluto 3: "When one creates a loc_proxy one must specify which interface(s) one plans on using.
This is done by passing an integer equal to the sum of 2^n for each interface. So if you want
interfaces 0 and 3 you pass 9"; thereafter ``get_pose(n)`` reads interface ``n``.  Setting a pose
(Pluto 7.1): stop the estimator, ``set_pose(pose, -1)`` (a robot pose), wait until the setter has
changed, start the estimator again — ``pose_i`` shows it.

The setter is the cmdFlags of the localModule's Post_Pose info, which it publishes on every
accepted write (transient local: a proxy started late knows it at once).
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from wurde_core import CommsManager, RunState
from wurde_core.interfaces import LocalizationPose

from .streams import POST_POSE, STREAMS, USER_SETTER, LocPose, read_pose, write_pose

__all__ = ['LocProxy']


class LocProxy:
    """The streams of ``mask`` (sum of 2**n) as consumers of ``manager``; queue mode optional."""

    def __init__(self, manager: CommsManager, mask: int, *, queue_mode: bool = False) -> None:
        """Register the streams of ``mask`` (and Post_Pose, for the setter) as consumers.

        :param manager: the program's CommsManager; the streams are registered with it.
        :param mask: the interfaces used, the sum of ``2**n`` for each stream ``n`` in 0..4 (Pluto 3:
            9 for interfaces 0 and 3).
        :param queue_mode: keep every sample for :meth:`get_poses` rather than only the newest.
        :raises ValueError: ``mask`` is not in 1..31.
        """
        if not 0 < mask < 2 ** len(STREAMS):
            raise ValueError(f'mask {mask}: the sum of 2**n for the interfaces n = 0..4 used (1..31)')
        self.manager = manager
        self.mask = mask
        self.streams: dict[int, LocalizationPose] = {}
        self._latest: dict[int, LocPose] = {}
        for n in [*(n for n in range(len(STREAMS)) if mask & (1 << n)), POST_POSE]:
            if n in self.streams:
                continue
            obj = LocalizationPose(STREAMS[n])
            obj.set_queue_mode(queue_mode)
            manager.register_consumer(obj)
            self.streams[n] = obj
        self.streams[POST_POSE].set_auto_timestamp(False)
        self._setter: int | None = None
        #: A pose written while the localModule's reader was not matched yet, to send once it is.
        self._held = False

    def _check(self, n: int) -> LocalizationPose:
        if not 0 <= n < len(STREAMS) or not self.mask & (1 << n):
            raise ValueError(f'interface {n} is not in the mask {self.mask}')
        return self.streams[n]

    def update(self) -> bool:
        """Send a held pose (see :meth:`set_pose`) if the localModule's reader is matched now;
        every other method of the proxy does this too.  Whether a pose is still held."""
        posts = self.streams[POST_POSE]
        if self._held and posts.peers('request'):
            self._held = not posts.publish_request()
        return self._held

    def get_pose(self, n: int) -> LocPose | None:
        """The newest pose of interface ``n`` taken in so far.

        :param n: the stream's number, 0..4 (:mod:`pluto_nav.streams`); it must be in the mask.
        :returns: the pose, or None before the first one arrived.
        :raises ValueError: ``n`` is not in the proxy's mask.
        """
        self.update()
        obj = self._check(n)
        while obj.get_next_data():
            self._latest[n] = read_pose(obj.data)
        return self._latest.get(n)

    def get_poses(self, n: int) -> list[LocPose]:
        """Every pose of interface ``n`` taken in since the last call (queue mode keeps them all).

        :param n: the stream's number, 0..4; it must be in the mask.
        :returns: the poses, oldest first; empty when none came.
        :raises ValueError: ``n`` is not in the proxy's mask.
        """
        self.update()
        obj = self._check(n)
        poses = []
        while obj.get_next_data():
            poses.append(read_pose(obj.data))
        if poses:
            self._latest[n] = poses[-1]
        return poses

    @property
    def setter(self) -> int | None:
        """The localization's current setter (None until the localModule has been heard)."""
        self.update()
        posts = self.streams[POST_POSE]
        while posts.get_next_info():
            self._setter = int(posts.info.cmd_flags.get_value())
        return self._setter

    def set_pose(self, pose: tuple[float, float, float], setter: int = USER_SETTER, *,
                 covariance: np.ndarray | None = None, stamp: float = 0.0) -> bool:
        """Write ``pose`` to Post_Pose; the localModule refuses a setter that is not allowed now.

        A request channel keeps nothing for a reader that matches later, so a pose written before
        the localModule's reader is matched is held (the newest one) and sent by the proxy's next
        call once it is.

        :param pose: ``(x, y, theta)`` in the map frame, metres and radians.
        :param setter: the cmdFlags: negative (default ``USER_SETTER``) a robot pose, else the
            estimator's setter for a laser pose; 0 releases the setter.
        :param covariance: 3x3 over (x, y, theta); None sends zeros.
        :param stamp: the time the laser pose belongs to, seconds; 0 means now.
        :returns: whether it was sent now (False: held, or not sendable in this state).
        """
        value = LocPose(pose=(pose[0], pose[1], 0.0, pose[2], 0.0, 0.0), setter=setter, stamp=stamp,
                        covariance=np.zeros((3, 3)) if covariance is None else np.asarray(covariance))
        posts = self.streams[POST_POSE]
        write_pose(posts.requests, value)
        if posts.peers('request'):
            self._held = False
            return posts.publish_request()
        self._held = True
        return False

    def wait_for_setter(self, accept: int | Callable[[int], bool], timeout: float) -> bool:
        """Run the manager's loop until the setter is ``accept``.

        :param accept: the setter value awaited, or a test on the setter.
        :param timeout: seconds to wait at most.
        :returns: True once it is; False on timeout or Quit.
        """
        test = accept if callable(accept) else (lambda value: value == accept)
        deadline = time.monotonic() + timeout
        while True:
            current = self.setter
            if current is not None and test(current):
                return True
            if time.monotonic() >= deadline or self.manager.run_update() != RunState.RUN:
                return False
