"""The compressed extended Kalman filter (CEKF) of Pluto's slamModule (Pluto 7.2).

Guivant & Nebot, "Optimization of the simultaneous localization and map-building algorithm for
real-time implementation", IEEE Trans. Robotics and Automation 17(3), 2001.  The state is a robot
block (the laser pose, 3 numbers) and one block per landmark (2 numbers: a wall's line).  The
landmarks are split into an *active* set ``A`` (those near the robot: every prediction and
measurement involves only the robot and ``A``) and a *passive* rest ``B``.  While the robot works
in ``A`` the filter keeps ``P_AA`` and ``x_A`` exactly and, instead of touching ``B``, gathers three
auxiliary matrices from the start of the phase (subscript 0):

- ``Phi``: ``P_AB = Phi P_A0B``; a prediction ``x_A <- f(x_A)`` with Jacobian ``J`` gives
  ``Phi <- J Phi``; an update with gain ``K = P_AA H^T S^-1`` gives ``Phi <- (I - K H) Phi``; a
  landmark initialised from the robot with Jacobian ``G`` adds the rows ``G Phi_robot``;
- ``psi``: ``P_BB = P_BB0 - P_BA0 psi P_A0B``, ``psi <- psi + (H Phi)^T S^-1 (H Phi)``;
- ``theta``: ``x_B = x_B0 + P_BA0 theta``, ``theta <- theta + (H Phi)^T S^-1 v``.

An update therefore costs ``O(|A|^2)`` whatever the size of the map.  :meth:`commit` (the *global
update*, done when the robot leaves its local area, and before anything reads the whole state)
applies the three to ``B`` in ``O(|B|^2 |A0|)`` and starts a new phase; :meth:`activate` commits
and chooses a new active set.  The result is the full EKF's, exactly (the test compares the two).

Landmarks are named by integer keys the caller chooses; the filter stores them in slots of arrays
that grow as needed, and a slot freed by :meth:`remove` is reused only after the next commit.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np
import scipy.linalg
from numpy.typing import ArrayLike, NDArray

__all__ = ['BLOCK', 'ROBOT', 'CompressedEKF']

#: Sizes of the robot's block and of one landmark's.
ROBOT = 3
BLOCK = 2


class CompressedEKF:
    """Robot and landmarks, with the compressed update (see the module's description).

    :param robot_mean: the robot's initial state.
    :param robot_covariance: its covariance (symmetric, positive semi-definite).
    """

    # The phase's state, set by _start_phase: positions of the active keys, A0's indices, x_A,
    # P_AA, whether Phi, psi and theta are kept, and the three.
    _position: dict[int, int]
    _a0: NDArray
    _xa: NDArray
    _paa: NDArray
    _tracking: bool
    _phi: NDArray
    _psi: NDArray
    _theta: NDArray

    def __init__(self, robot_mean: ArrayLike, robot_covariance: ArrayLike) -> None:
        capacity = 16
        self._x = np.zeros(ROBOT + BLOCK * capacity)
        self._p = np.zeros((len(self._x), len(self._x)))
        self._x[:ROBOT] = np.asarray(robot_mean, dtype=np.float64).reshape(ROBOT)
        cov = np.asarray(robot_covariance, dtype=np.float64).reshape(ROBOT, ROBOT)
        self._p[:ROBOT, :ROBOT] = cov
        self._slot: dict[int, int] = {}
        self._free: list[int] = list(range(capacity - 1, -1, -1))
        self._freed: list[int] = []          # freed in this phase: reusable after a commit
        self._active: list[int] = []
        self._start_phase()

    # -- reading ----------------------------------------------------------------------------------

    def __len__(self) -> int:
        """Number of landmarks."""
        return len(self._slot)

    def __contains__(self, key: object) -> bool:
        return key in self._slot

    @property
    def keys(self) -> list[int]:
        """All landmark keys, in the order they were added."""
        return list(self._slot)

    @property
    def active(self) -> list[int]:
        """The active landmarks' keys, in the order of the active state."""
        return list(self._active)

    @property
    def robot_mean(self) -> NDArray:
        return self._xa[:ROBOT].copy()

    @property
    def robot_covariance(self) -> NDArray:
        return self._paa[:ROBOT, :ROBOT].copy()

    @property
    def active_mean(self) -> NDArray:
        """``x_A``: the robot, then the active landmarks (read-only view)."""
        view = self._xa.view()
        view.flags.writeable = False
        return view

    @property
    def active_covariance(self) -> NDArray:
        """``P_AA`` (read-only view)."""
        view = self._paa.view()
        view.flags.writeable = False
        return view

    def local_index(self, key: int) -> int:
        """Where landmark ``key``'s block starts in the active state.

        :raises KeyError: if ``key`` is not active.
        """
        try:
            return ROBOT + BLOCK * self._position[key]
        except KeyError:
            raise KeyError(f'landmark {key} is not active') from None

    def means(self, keys: Iterable[int]) -> NDArray:
        """``(K, 2)`` current means of any landmarks (passive ones with the phase's correction,
        without committing it)."""
        keys = [int(k) for k in keys]
        out = np.empty((len(keys), BLOCK))
        position = np.array([self._position.get(k, -1) for k in keys], dtype=np.intp)
        active = position >= 0
        out[active] = self._xa[ROBOT:].reshape(-1, BLOCK)[position[active]]
        for row in np.flatnonzero(~active):
            index = self._indices(self._slot[keys[row]])
            out[row] = self._x[index]
            if len(self._theta):
                out[row] += self._p[np.ix_(index, self._a0)] @ self._theta
        return out

    def state(self) -> tuple[list[int], NDArray, NDArray]:
        """Commit, then ``(keys, mean, covariance)`` of the whole state: the robot, then the
        landmarks in ``keys`` order (copies)."""
        self.commit()
        keys = self.keys
        index = np.concatenate([np.arange(ROBOT)] + [self._indices(self._slot[k]) for k in keys])
        return keys, self._x[index].copy(), self._p[np.ix_(index, index)].copy()

    # -- the filter -------------------------------------------------------------------------------

    def predict(self, robot_mean: ArrayLike, jacobian: ArrayLike, noise: ArrayLike) -> None:
        """The robot moves: its new mean, ``J = d(new)/d(old)`` and the added noise (3x3)."""
        j = np.asarray(jacobian, dtype=np.float64).reshape(ROBOT, ROBOT)
        p = self._paa
        p[:ROBOT, :] = j @ p[:ROBOT, :]
        p[:, :ROBOT] = p[:, :ROBOT] @ j.T
        p[:ROBOT, :ROBOT] += np.asarray(noise, dtype=np.float64).reshape(ROBOT, ROBOT)
        p[:ROBOT, :ROBOT] = 0.5 * (p[:ROBOT, :ROBOT] + p[:ROBOT, :ROBOT].T)
        self._xa[:ROBOT] = np.asarray(robot_mean, dtype=np.float64).reshape(ROBOT)
        if self._tracking:
            self._phi[:ROBOT, :] = j @ self._phi[:ROBOT, :]

    def update(self, columns: Sequence[int] | NDArray, jacobian: ArrayLike, noise: ArrayLike,
               innovation: ArrayLike) -> None:
        """An EKF update with measurements of the active state only.

        :param columns: indices into the active state that the measurements depend on.
        :param jacobian: ``(m, len(columns))``: ``H`` restricted to those columns.
        :param noise: ``(m, m)`` measurement covariance ``R``.
        :param innovation: ``(m,)`` ``v = z - h(x)`` (angles already wrapped by the caller).
        :raises numpy.linalg.LinAlgError: if ``S`` is not positive definite.
        """
        cols = np.asarray(columns, dtype=np.intp)
        h = np.asarray(jacobian, dtype=np.float64)
        v = np.asarray(innovation, dtype=np.float64).reshape(-1)
        pht = self._paa[:, cols] @ h.T                                   # (a, m)
        s = h @ pht[cols, :] + np.asarray(noise, dtype=np.float64)
        factor = scipy.linalg.cho_factor(0.5 * (s + s.T), check_finite=False)
        w = scipy.linalg.cho_solve(factor, v, check_finite=False)
        self._xa += pht @ w
        self._paa -= pht @ scipy.linalg.cho_solve(factor, pht.T, check_finite=False)
        self._paa = 0.5 * (self._paa + self._paa.T)
        if self._tracking:
            h_phi = h @ self._phi[cols, :]                               # (m, a0)
            s_h_phi = scipy.linalg.cho_solve(factor, h_phi, check_finite=False)
            self._psi += h_phi.T @ s_h_phi
            self._theta += h_phi.T @ w
            self._phi -= pht @ s_h_phi

    def add(self, key: int, mean: ArrayLike, robot_jacobian: ArrayLike, noise: ArrayLike) -> None:
        """A new active landmark initialised from the robot: ``l = g(robot, z)``.

        :param robot_jacobian: ``G = dg/d(robot)``, 2x3.
        :param noise: ``G_z R G_z^T``, 2x2, the part of its covariance that comes from ``z``.
        :raises ValueError: if ``key`` is taken.
        """
        if key in self._slot:
            raise ValueError(f'landmark {key} exists already')
        if not self._free:
            self._grow()
        self._slot[key] = self._free.pop()
        g = np.asarray(robot_jacobian, dtype=np.float64).reshape(BLOCK, ROBOT)
        rows = g @ self._paa[:ROBOT, :]
        corner = rows[:, :ROBOT] @ g.T + np.asarray(noise, dtype=np.float64).reshape(BLOCK, BLOCK)
        self._paa = np.block([[self._paa, rows.T], [rows, 0.5 * (corner + corner.T)]])
        self._xa = np.concatenate([self._xa, np.asarray(mean, dtype=np.float64).reshape(BLOCK)])
        if self._tracking:
            self._phi = np.vstack([self._phi, g @ self._phi[:ROBOT, :]])
        self._position[key] = len(self._active)
        self._active.append(key)

    def remove(self, key: int) -> None:
        """Forget landmark ``key`` (active or passive): marginalise it out.

        :raises KeyError: for an unknown key.
        """
        slot = self._slot.pop(key)
        self._freed.append(slot)
        position = self._position.pop(key, None)
        if position is None:
            return
        start = ROBOT + BLOCK * position
        keep = np.r_[0:start, start + BLOCK:len(self._xa)]
        self._xa = self._xa[keep]
        self._paa = self._paa[np.ix_(keep, keep)]
        if self._tracking:
            self._phi = self._phi[keep, :]
        del self._active[position]
        self._position = {k: i for i, k in enumerate(self._active)}

    def commit(self) -> None:
        """The global update: bring the passive landmarks up to date and start a new phase with
        the same active set."""
        now = self._active_indices()
        passive = [self._slot[k] for k in self._slot if k not in self._position]
        if passive:
            b = np.concatenate([self._indices(slot) for slot in passive])
            p_a0b = self._p[np.ix_(self._a0, b)]
            self._x[b] += p_a0b.T @ self._theta
            p_bb = self._p[np.ix_(b, b)] - p_a0b.T @ self._psi @ p_a0b
            self._p[np.ix_(b, b)] = 0.5 * (p_bb + p_bb.T)
            p_ab = self._phi @ p_a0b
            self._p[np.ix_(now, b)] = p_ab
            self._p[np.ix_(b, now)] = p_ab.T
        self._x[now] = self._xa
        self._p[np.ix_(now, now)] = self._paa
        self._free.extend(self._freed)
        self._freed = []
        self._start_phase()

    def activate(self, keys: Iterable[int]) -> None:
        """Commit, then make ``keys`` (in that order) the active landmarks.

        :raises KeyError: for an unknown key.
        """
        keys = list(dict.fromkeys(keys))
        for key in keys:
            if key not in self._slot:
                raise KeyError(f'no landmark {key}')
        self.commit()
        self._active = keys
        self._start_phase()

    # -- internals --------------------------------------------------------------------------------

    @staticmethod
    def _indices(slot: int) -> NDArray:
        start = ROBOT + BLOCK * slot
        return np.arange(start, start + BLOCK)

    def _active_indices(self) -> NDArray:
        return np.concatenate([np.arange(ROBOT)] +
                              [self._indices(self._slot[k]) for k in self._active])

    def _start_phase(self) -> None:
        """``A0 = A``; ``Phi = I``, ``psi = 0``, ``theta = 0``; the local copies from the full
        state.  With no passive landmark (a map within the laser's reach) there is nothing for
        the three to bring up to date, and they are not kept: the filter is the plain EKF."""
        self._position = {k: i for i, k in enumerate(self._active)}
        self._a0 = self._active_indices()
        self._xa = self._x[self._a0].copy()
        self._paa = self._p[np.ix_(self._a0, self._a0)].copy()
        self._tracking = len(self._slot) > len(self._active)
        size = len(self._a0) if self._tracking else 0
        self._phi = np.eye(size)
        self._psi = np.zeros((size, size))
        self._theta = np.zeros(size)

    def _grow(self) -> None:
        """Double the number of slots (only the full arrays; the phase's indices stay valid)."""
        capacity = (len(self._x) - ROBOT) // BLOCK
        x = np.zeros(ROBOT + 2 * BLOCK * capacity)
        p = np.zeros((len(x), len(x)))
        x[:len(self._x)] = self._x
        p[:len(self._x), :len(self._x)] = self._p
        self._x, self._p = x, p
        self._free.extend(range(2 * capacity - 1, capacity - 1, -1))
