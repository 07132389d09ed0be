"""The compressed EKF computes exactly what a plain EKF over the whole state computes."""

from __future__ import annotations

import numpy as np
import pytest

from pluto_nav.compressed_ekf import BLOCK, ROBOT, CompressedEKF


class DenseEKF:
    """The reference: every operation on the whole mean and covariance, in key order."""

    def __init__(self, mean, cov) -> None:
        self.x = np.array(mean, dtype=float)
        self.p = np.array(cov, dtype=float)
        self.keys: list[int] = []

    def index(self, key: int) -> int:
        return ROBOT + BLOCK * self.keys.index(key)

    def predict(self, mean, j, q) -> None:
        f = np.eye(len(self.x))
        f[:ROBOT, :ROBOT] = j
        self.p = f @ self.p @ f.T
        self.p[:ROBOT, :ROBOT] += q
        self.x[:ROBOT] = mean

    def update(self, columns, h, r, v) -> None:
        full = np.zeros((len(v), len(self.x)))
        full[:, columns] = h
        s = full @ self.p @ full.T + r
        k = self.p @ full.T @ np.linalg.inv(s)
        self.x = self.x + k @ v
        self.p = self.p - k @ s @ k.T

    def add(self, key, mean, g, noise) -> None:
        rows = g @ self.p[:ROBOT, :]
        corner = rows[:, :ROBOT] @ g.T + noise
        self.p = np.block([[self.p, rows.T], [rows, corner]])
        self.x = np.concatenate([self.x, mean])
        self.keys.append(key)

    def remove(self, key) -> None:
        start = self.index(key)
        keep = np.r_[0:start, start + BLOCK:len(self.x)]
        self.x, self.p = self.x[keep], self.p[np.ix_(keep, keep)]
        self.keys.remove(key)


def _random_spd(rng: np.random.Generator, n: int, scale: float) -> np.ndarray:
    a = rng.normal(size=(n, n))
    return scale * (a @ a.T + n * np.eye(n))


def _columns(ekf: CompressedEKF, dense: DenseEKF, keys: list[int]) -> tuple[list[int], list[int]]:
    local = list(range(ROBOT)) + [ekf.local_index(k) + i for k in keys for i in range(BLOCK)]
    full = list(range(ROBOT)) + [dense.index(k) + i for k in keys for i in range(BLOCK)]
    return local, full


@pytest.mark.parametrize('seed', [1, 2, 3])
def test_compressed_equals_dense_over_phases(seed: int) -> None:
    rng = np.random.default_rng(seed)
    robot_cov = _random_spd(rng, ROBOT, 0.01)
    ekf = CompressedEKF([1.0, 2.0, 0.3], robot_cov)
    dense = DenseEKF([1.0, 2.0, 0.3], robot_cov)
    next_key = 0
    for step in range(120):
        choice = rng.random()
        if choice < 0.3 or len(ekf) < 2:
            g = rng.normal(size=(BLOCK, ROBOT))
            noise = _random_spd(rng, BLOCK, 1e-3)
            mean = rng.normal(size=BLOCK)
            ekf.add(next_key, mean, g, noise)
            dense.add(next_key, mean, g, noise)
            next_key += 1
        elif choice < 0.55:
            mean = rng.normal(size=ROBOT)
            j = np.eye(ROBOT) + 0.1 * rng.normal(size=(ROBOT, ROBOT))
            q = _random_spd(rng, ROBOT, 1e-3)
            ekf.predict(mean, j, q)
            dense.predict(mean, j, q)
        elif choice < 0.85 and ekf.active:
            seen = list(rng.choice(ekf.active, size=min(3, len(ekf.active)), replace=False))
            local, full = _columns(ekf, dense, seen)
            h = rng.normal(size=(2 * len(seen), len(local)))
            r = _random_spd(rng, 2 * len(seen), 1e-2)
            v = 0.1 * rng.normal(size=2 * len(seen))
            ekf.update(local, h, r, v)
            dense.update(full, h, r, v)
        elif choice < 0.92:
            key = int(rng.choice(ekf.keys))
            ekf.remove(key)
            dense.remove(key)
        else:
            keys = ekf.keys
            chosen = rng.choice(keys, size=rng.integers(0, len(keys) + 1), replace=False)
            ekf.activate(chosen.tolist())
        if step % 17 == 0:
            # Reading passive means mid-phase must not disturb anything.
            np.testing.assert_allclose(ekf.means(dense.keys),
                                       dense.x[ROBOT:].reshape(-1, BLOCK), atol=1e-9)
    keys, mean, cov = ekf.state()
    order = [dense.index(k) + i for k in keys for i in range(BLOCK)]
    np.testing.assert_allclose(mean, dense.x[list(range(ROBOT)) + order], atol=1e-9)
    np.testing.assert_allclose(cov, dense.p[np.ix_(list(range(ROBOT)) + order,
                                                   list(range(ROBOT)) + order)], atol=1e-9)
    assert np.linalg.eigvalsh(cov)[0] > 0.0


def test_passive_landmarks_are_untouched_until_commit() -> None:
    """The point of compression: an update in the local area leaves the passive arrays alone."""
    ekf = CompressedEKF([0.0, 0.0, 0.0], 1e-4 * np.eye(3))
    g = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
    for key in range(4):
        ekf.add(key, [0.1 * key, 5.0], g, 1e-4 * np.eye(2))
    ekf.activate([0, 1])
    before = ekf._p.copy()
    local = [0, 1, 2, ekf.local_index(1), ekf.local_index(1) + 1]
    ekf.update(local, np.array([[0.0, 0.0, -1.0, 1.0, 0.0], [-1.0, 0.0, 0.0, 0.0, 1.0]]),
               1e-4 * np.eye(2), np.array([0.01, -0.02]))
    np.testing.assert_array_equal(ekf._p, before)
    moved = ekf.means([2, 3])
    ekf.commit()
    np.testing.assert_allclose(ekf.means([2, 3]), moved, atol=1e-12)
    assert not np.array_equal(ekf._p, before)


def test_errors() -> None:
    ekf = CompressedEKF([0.0, 0.0, 0.0], np.eye(3))
    ekf.add(7, [0.0, 1.0], np.zeros((2, 3)), np.eye(2))
    with pytest.raises(ValueError, match='exists'):
        ekf.add(7, [0.0, 1.0], np.zeros((2, 3)), np.eye(2))
    with pytest.raises(KeyError):
        ekf.activate([8])
    ekf.activate([])
    with pytest.raises(KeyError, match='not active'):
        ekf.local_index(7)
