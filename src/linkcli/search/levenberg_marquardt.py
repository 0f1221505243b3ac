"""Levenberg-Marquardt on many candidates at once, inside a box (numpy, no BLAS).

Each row z of the batch takes the step s solving (J^T J + lambda D) s = -J^T r with
D = diag(J^T J) (Marquardt's scaling; Marquardt 1963, More 1978), clipped to the box;
the step is kept if it lowers |r|^2, and lambda shrinks by 3 (kept) or grows by 4
(refused). A variable at a bound whose gradient pushes out of the box is frozen for the
step. The rows are stacked (one residual call for all of them); every linear system is
solved by `linkcli.search.linalg`, so the steps do not follow the machine's BLAS kernel.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from linkcli.search import linalg
from linkcli.search.budget import Budget


class BoxedLeastSquares(Protocol):
    """A batch of least-squares problems sharing one box: residuals (N, m) of rows z (N, k)
    picked by `rows` (indices into the batch), their Jacobians (N, m, k) given the
    residuals r0, the bounds lo, hi (k,), and the budget the residuals count against."""

    lo: np.ndarray
    hi: np.ndarray
    budget: Budget

    def residuals(self, z: np.ndarray, rows) -> np.ndarray: ...

    def jacobian(self, z: np.ndarray, rows, r0: np.ndarray) -> np.ndarray: ...


def batch_lm(problem: BoxedLeastSquares, z, iterations: int, reserve: int = 0):
    """Levenberg-Marquardt on every row of z at once, leaving `reserve` evaluations of the
    budget unspent (a Jacobian costs 2k + 1 per row); returns (z, cost, converged): a row
    has converged when a step gains less than 1e-12 of its cost, when no step gains
    anything (damping above 1e10), or at an exact fit."""
    z = z.copy()
    k = z.shape[1]
    if k == 0 or problem.budget.left - reserve < len(z):
        return z, np.full(len(z), np.inf), np.zeros(len(z), dtype=bool)
    r = problem.residuals(z, slice(None))
    f = np.einsum("ij,ij->i", r, r)
    lam = np.full(len(z), 1e-3)
    jac = None
    stale = np.ones(len(z), dtype=bool)  # Jacobian to (re)compute
    active = np.ones(len(z), dtype=bool)
    lo, hi = problem.lo, problem.hi
    for _ in range(iterations):
        rows = np.flatnonzero(active)
        if len(rows) == 0 or problem.budget.left - reserve < len(rows) * (2 * k + 1):
            break
        need = rows[stale[rows]]
        if jac is None:
            jac = np.zeros((len(z), r.shape[1], k))
        if len(need):
            jac[need] = problem.jacobian(z[need], need, r[need])
            stale[need] = False
        j = jac[rows]
        g = np.einsum("nmk,nm->nk", j, r[rows])
        h = np.einsum("nmk,nml->nkl", j, j)
        zr = z[rows]
        frozen = (((zr <= lo + 1e-12 * (np.abs(lo) + 1)) & (g > 0))
                  | ((zr >= hi - 1e-12 * (np.abs(hi) + 1)) & (g < 0)))
        keep = ~frozen
        h = h * keep[:, :, None] * keep[:, None, :]
        g = g * keep
        diag = np.einsum("nkk->nk", h)
        damp = lam[rows, None] * (diag + 1e-12 * diag.max(axis=1, keepdims=True)) + frozen + 1e-300
        a = h + np.einsum("nk,kl->nkl", damp, np.eye(k))
        step = -linalg.solve_spd(a, g)
        step = np.nan_to_num(step) * keep
        znew = np.clip(zr + step, lo, hi)
        rnew = problem.residuals(znew, rows)
        fnew = np.einsum("ij,ij->i", rnew, rnew)
        ok = fnew < f[rows]
        acc = rows[ok]
        small = ok & (f[rows] - fnew <= 1e-12 * f[rows])
        z[acc], r[acc], stale[acc] = znew[ok], rnew[ok], True
        f_old = f[rows]
        f[acc] = fnew[ok]
        lam[rows] = np.where(ok, np.maximum(lam[rows] / 3.0, 1e-12), lam[rows] * 4.0)
        done = small | (lam[rows] > 1e10) | (f[rows] < 1e-30) | (~ok & (f_old < 1e-30))
        active[rows[done]] = False
    return z, f, ~active
