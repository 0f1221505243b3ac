"""Jacobians shaped like an arrow, and their damped normal equations in O(n) (numpy, no BLAS).

In a least-squares fit through n poses or targets, each pose's own input angle moves that
pose's residuals alone: the Jacobian's p leading columns (the linkage) are dense, and each
of its n trailing columns (the angles) touches only the rows of its pose. Stored as

    dense (N, m, p), local (N, m): row r's slope along its owner's angle, owner (m,) in
    [-1, n) (-1: a row no angle moves: a Grashof or full-turn constraint),

J^T J is an arrow, a dense p x p block bordered by a diagonal:

    [ A    B ]   A = Jw^T Jw,   B_ij = sum over the rows r of angle j of Jw_ri t_r,
    [ B^T  C ]   C = diag(c),   c_j = sum over the rows of angle j of t_r^2,

and the damped system (J^T J + D) x = y is solved by eliminating the diagonal block (the
Schur complement S = A + D_w - B (C + D_t)^-1 B^T, Golub & Van Loan, Matrix Computations,
4th ed., sec. 3.2.10 on block elimination): O(n p^2) a row instead of O((n + p)^3) for the
dense system, and O(n p) memory instead of O(n^2). Every sum is an `einsum` without BLAS
(linkcli.search.linalg), so the steps are the same on every machine.
"""

from __future__ import annotations

import numpy as np

from linkcli.search import linalg


class Arrow:
    """The Jacobians (N rows of a batch) of an arrow-shaped least-squares problem: `dense`
    (N, m, p), `local` (N, m) and the rows' owners (m,) (see the module docstring). Sums
    over an angle's rows are segment sums (`np.add.reduceat` over the rows sorted by
    owner): O(m) work, whatever n."""

    def __init__(self, dense: np.ndarray, local: np.ndarray, owner: np.ndarray, n: int) -> None:
        self.dense, self.local, self.owner, self.n = dense, local, owner, n
        self.order = np.argsort(owner, kind="stable")  # the rows no angle moves (-1) first
        sorted_owner = owner[self.order]
        self.starts = np.searchsorted(sorted_owner, np.arange(n))  # each angle's first row
        if n and not np.all(np.diff(np.append(self.starts, len(owner))) > 0):
            raise ValueError("every angle needs a row of its own")

    @property
    def p(self) -> int:
        return self.dense.shape[2]

    @classmethod
    def empty(cls, size: int, like: Arrow) -> Arrow:
        return cls(np.zeros((size,) + like.dense.shape[1:]), np.zeros((size,) + like.local.shape[1:]),
                   like.owner, like.n)

    def take(self, rows) -> Arrow:
        out = Arrow.__new__(Arrow)
        out.__dict__.update(self.__dict__)
        out.dense, out.local = self.dense[rows], self.local[rows]
        return out

    def put(self, rows, other: Arrow) -> None:
        self.dense[rows], self.local[rows] = other.dense, other.local

    def _per_angle(self, rows: np.ndarray) -> np.ndarray:
        """Sums over each angle's rows of rows (N, m, ...) -> (N, n, ...)."""
        if self.n == 0:
            return np.zeros(rows.shape[:1] + (0,) + rows.shape[2:])
        return np.add.reduceat(rows[:, self.order], self.starts, axis=1)

    def gradient(self, r: np.ndarray) -> np.ndarray:
        """J^T r (N, p + n)."""
        gw = np.einsum("nmp,nm->np", self.dense, r, optimize=False)
        return np.concatenate([gw, self._per_angle(self.local * r)], axis=1)

    def normal(self, keep: np.ndarray) -> ArrowNormal:
        """J^T J with the variables not `keep` (N, p + n) left out (their rows and columns 0)."""
        p = self.p
        kw, kt = keep[:, :p], keep[:, p:]
        dt = np.ascontiguousarray(np.transpose(self.dense, (0, 2, 1)))
        a = np.einsum("npm,nqm->npq", dt, dt, optimize=False) * kw[:, :, None] * kw[:, None, :]
        b = np.transpose(self._per_angle(self.dense * self.local[:, :, None]), (0, 2, 1))
        b = b * kw[:, :, None] * kt[:, None, :]
        c = self._per_angle(self.local * self.local) * kt
        return ArrowNormal(a, b, c)


class ArrowNormal:
    """J^T J of an Arrow: a (N, p, p), b (N, p, n), c (N, n)."""

    def __init__(self, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> None:
        self.a, self.b, self.c = a, b, c

    def diagonal(self) -> np.ndarray:
        return np.concatenate([np.einsum("npp->np", self.a), self.c], axis=1)

    def solve(self, damp: np.ndarray, y: np.ndarray) -> np.ndarray:
        """x (N, p + n) with (J^T J + diag(damp)) x = y, by eliminating the diagonal block;
        NaN where the Schur complement is not positive definite (linalg.solve_spd)."""
        p = self.a.shape[1]
        ct = self.c + damp[:, p:]
        yw, yt = y[:, :p], y[:, p:]
        if p == 0:
            return yt / ct
        scaled = self.b / ct[:, None, :]  # B (C + D_t)^-1
        s = self.a - np.einsum("npj,nqj->npq", scaled, self.b, optimize=False)
        s = s + np.einsum("np,pq->npq", damp[:, :p], np.eye(p))
        xw = linalg.solve_spd(s, yw - np.einsum("npj,nj->np", scaled, yt, optimize=False))
        xt = (yt - np.einsum("npj,np->nj", self.b, xw, optimize=False)) / ct
        return np.concatenate([xw, xt], axis=1)
