"""A 2-D pose graph and its least-squares solution (Lu and Milios; Grisetti et al., "A tutorial on
graph-based SLAM", 2010).

Nodes are poses ``(x, y, theta)``; an edge ``i -> j`` says "seen from node i, node j is at ``z``"
with an information matrix.  :meth:`PoseGraph.optimize` moves every node but the first to the
poses that best explain all edges: Gauss-Newton on the sparse normal equations (scipy's sparse LU;
a building's graph of a few thousand nodes solves in tens of milliseconds).  Edges may be
*robust*: their weight falls off beyond ``robust`` standard deviations (Huber), so that one wrong
loop closure among right ones bends the map a little instead of folding it.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import sparse
from scipy.sparse.linalg import spsolve

from .geometry import wrap

__all__ = ['Edge', 'PoseGraph', 'Solution']

_R3 = np.arange(3)


@dataclasses.dataclass(frozen=True)
class Edge:
    """``i -> j``: node ``j`` at ``z`` in node ``i``'s frame; ``robust`` 0 for a plain edge."""

    i: int
    j: int
    z: tuple[float, float, float]
    information: NDArray
    robust: float = 0.0
    kind: str = ''


@dataclasses.dataclass(frozen=True)
class Solution:
    """:ivar iterations: Gauss-Newton steps taken.
    :ivar chi2: each edge's squared Mahalanobis error at the solution.
    :ivar weights: each edge's robust weight (1 for plain edges and inliers).
    """

    iterations: int
    chi2: NDArray
    weights: NDArray


class PoseGraph:
    """Nodes and edges; :meth:`optimize` solves in place."""

    def __init__(self) -> None:
        self.poses = np.zeros((0, 3))
        self.edges: list[Edge] = []
        self._arrays: tuple[NDArray, ...] | None = None

    def add_node(self, pose: ArrayLike) -> int:
        self.poses = np.vstack([self.poses, np.asarray(pose, dtype=np.float64).reshape(1, 3)])
        return len(self.poses) - 1

    def add_edge(self, edge: Edge) -> None:
        if not (0 <= edge.i < len(self.poses) and 0 <= edge.j < len(self.poses)) or edge.i == edge.j:
            raise ValueError(f'edge {edge.i} -> {edge.j} of a graph of {len(self.poses)} nodes')
        self.edges.append(edge)
        self._arrays = None

    def __len__(self) -> int:
        return len(self.poses)

    def _edge_arrays(self) -> tuple[NDArray, ...]:
        if self._arrays is None:
            e = self.edges
            self._arrays = (np.array([x.i for x in e], dtype=np.intp), np.array([x.j for x in e], dtype=np.intp),
                            np.array([x.z for x in e], dtype=np.float64).reshape(-1, 3),
                            np.array([x.information for x in e], dtype=np.float64).reshape(-1, 3, 3),
                            np.array([x.robust for x in e], dtype=np.float64))
        return self._arrays

    def errors(self, poses: NDArray | None = None) -> NDArray:
        """Each edge's error ``(E, 3)`` at ``poses`` (default: the graph's)."""
        i, j, z, _, _ = self._edge_arrays()
        x = self.poses if poses is None else poses
        return _errors(x[i], x[j], z)[0]

    def optimize(self, *, iterations: int = 10, tolerance: float = 1e-6) -> Solution:
        """Gauss-Newton until the largest step is below ``tolerance`` (m, rad); node 0 fixed."""
        if not self.edges:
            return Solution(0, np.zeros(0), np.zeros(0))
        i, j, z, information, robust = self._edge_arrays()
        n = len(self.poses)
        x = self.poses.copy()
        done = 0
        for done in range(1, iterations + 1):
            xi, xj = x[i], x[j]
            error, a, b = _errors(xi, xj, z)
            chi2 = np.einsum('ei,eij,ej->e', error, information, error)
            weight = _huber(chi2, robust)
            w = information * weight[:, None, None]
            atw = np.einsum('eki,ekl->eil', a, w)
            btw = np.einsum('eki,ekl->eil', b, w)
            blocks = ((i, i, atw @ a), (i, j, atw @ b), (j, i, btw @ a), (j, j, btw @ b))
            rows = np.concatenate([np.repeat(3 * p, 9) + np.tile(np.repeat(_R3, 3), len(p)) for p, _, _ in blocks])
            cols = np.concatenate([np.repeat(3 * q, 9) + np.tile(np.tile(_R3, 3), len(q)) for _, q, _ in blocks])
            values = np.concatenate([m.reshape(-1) for _, _, m in blocks])
            hessian = sparse.coo_matrix((values, (rows, cols)), shape=(3 * n, 3 * n)).tocsc()
            gradient = np.zeros(3 * n)
            np.add.at(gradient, (3 * i[:, None] + _R3).reshape(-1), np.einsum('eil,el->ei', atw, error).reshape(-1))
            np.add.at(gradient, (3 * j[:, None] + _R3).reshape(-1), np.einsum('eil,el->ei', btw, error).reshape(-1))
            anchor = np.zeros(3 * n)
            anchor[:3] = 1e12                       # node 0 holds the map's frame
            step = spsolve(hessian + sparse.diags(anchor + 1e-9, format='csc'), -gradient)
            x = x + step.reshape(-1, 3)
            x[:, 2] = wrap(x[:, 2])
            if np.max(np.abs(step)) < tolerance:
                break
        self.poses = x
        error = _errors(x[i], x[j], z)[0]
        chi2 = np.einsum('ei,eij,ej->e', error, information, error)
        return Solution(done, chi2, _huber(chi2, robust))


def _errors(xi: NDArray, xj: NDArray, z: NDArray) -> tuple[NDArray, NDArray, NDArray]:
    """Errors ``relative(xi, xj) - z`` (angle wrapped) and their Jacobians by ``xi`` and ``xj``."""
    c, s = np.cos(xi[:, 2]), np.sin(xi[:, 2])
    dx, dy = xj[:, 0] - xi[:, 0], xj[:, 1] - xi[:, 1]
    error = np.column_stack([c * dx + s * dy - z[:, 0], -s * dx + c * dy - z[:, 1],
                             wrap(xj[:, 2] - xi[:, 2] - z[:, 2])])
    a = np.zeros((len(xi), 3, 3))
    b = np.zeros((len(xi), 3, 3))
    a[:, 0, 0], a[:, 0, 1], a[:, 0, 2] = -c, -s, -s * dx + c * dy
    a[:, 1, 0], a[:, 1, 1], a[:, 1, 2] = s, -c, -c * dx - s * dy
    a[:, 2, 2] = -1.0
    b[:, 0, 0], b[:, 0, 1], b[:, 1, 0], b[:, 1, 1], b[:, 2, 2] = c, s, -s, c, 1.0
    return error, a, b


def _huber(chi2: NDArray, robust: NDArray) -> NDArray:
    """Huber's weight on an edge whose Mahalanobis error exceeds ``robust`` (0: never).  Not a
    redescending kernel: a loop closure found after some drift starts far outside its own small
    covariance, and must still pull the map into place."""
    limit = robust ** 2
    return np.where((robust > 0) & (chi2 > limit), np.sqrt(limit / np.maximum(chi2, 1e-300)), 1.0)
