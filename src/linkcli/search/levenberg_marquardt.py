"""Levenberg-Marquardt on many candidates at once, inside a box (numpy, no BLAS).

Each row z of the batch takes the step s solving (J^T J + lambda D) s = -J^T r with
D = diag(J^T J) (Marquardt's scaling; Marquardt 1963, More 1978), clipped to the box;
the step is kept if it lowers |r|^2, and lambda shrinks by 3 (kept) or grows by 4
(refused). A variable at a bound whose gradient pushes out of the box is frozen for the
step. A problem may add one linear inequality c.z <= b (`linear`): a step that would cross
its plane becomes the model's minimizer on the plane (`_on_plane`), so the constraint is
held exactly, without a penalty's kink. The rows are stacked (one residual call for all
of them); every linear system is solved by `linkcli.search.linalg`, so the steps do not
follow the machine's BLAS kernel.

Optionally (`acceleration`, for problems without `linear`) each step gets the geodesic
acceleration of Transtrum & Sethna ("Improvements to the Levenberg-Marquardt algorithm
for nonlinear least-squares minimization", arXiv:1201.5885, 2012): with v the step above
and r_vv = (2 / h) ((r(z + h v) - r(z)) / h - J v) the residuals' second derivative along
it (h = GEODESIC_PROBE, one more residual call per row), a = -(J^T J + lambda D)^-1 J^T r_vv
and the step v + a / 2; where 2 |a| / |v| > GEODESIC_RATIO the acceleration is not trusted
and the plain step v is tried (their method refuses the step; near a minimum the probe's
second difference is round-off, and refusals only grew lambda). In long
curved valleys (a trade between a linkage's start angle and its lengths) it takes steps
several times longer than the plain step, which follows the valley's tangent.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from linkcli.search import linalg
from linkcli.search.budget import Budget

GEODESIC_PROBE = 0.1  # the step's share probed for the second derivative (Transtrum & Sethna)
GEODESIC_RATIO = 0.75  # largest 2 |a| / |v| accepted (their alpha)


class BoxedLeastSquares(Protocol):
    """A batch of least-squares problems sharing one box: residuals (N, m) of rows z (N, k)
    picked by `rows` (indices into the batch), their Jacobians (N, m, k) given the
    residuals r0, the bounds lo, hi (k,), and the budget the residuals count against;
    optionally `linear` = (c (k,), b), the constraint c.z <= b (None: none)."""

    lo: np.ndarray
    hi: np.ndarray
    budget: Budget

    def residuals(self, z: np.ndarray, rows) -> np.ndarray: ...

    def jacobian(self, z: np.ndarray, rows, r0: np.ndarray) -> np.ndarray: ...


def batch_lm(problem: BoxedLeastSquares, z, iterations: int, reserve: int = 0, enough: float = -1.0,
             acceleration: bool = False):
    """Levenberg-Marquardt on every row of z at once, leaving `reserve` evaluations of the
    budget unspent (a Jacobian costs 2k + 1 per row), and stopping every row once one
    costs `enough` or less; with geodesic `acceleration` (see the module docstring);
    returns (z, cost, converged): a row has converged when a step
    gains less than 1e-12 of its cost, when no step gains anything (damping above 1e10),
    or at an exact fit."""
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
    linear = getattr(problem, "linear", None)
    for _ in range(iterations):
        rows = np.flatnonzero(active)
        if len(rows) == 0 or f.min() <= enough or problem.budget.left - reserve < len(rows) * (2 * k + 1):
            break
        need = rows[stale[rows]]
        if jac is None:
            jac = np.zeros((len(z), r.shape[1], k))
        if len(need):
            jac[need] = problem.jacobian(z[need], need, r[need])
            stale[need] = False
        j = jac[rows]
        g = np.einsum("nmk,nm->nk", j, r[rows])
        jt = np.ascontiguousarray(np.transpose(j, (0, 2, 1)))  # rows of J^T: einsum's fast loop
        h = np.einsum("nkm,nlm->nkl", jt, jt)
        zr = z[rows]
        frozen = (((zr <= lo + 1e-12 * (np.abs(lo) + 1)) & (g > 0))
                  | ((zr >= hi - 1e-12 * (np.abs(hi) + 1)) & (g < 0)))
        keep = ~frozen
        h = h * keep[:, :, None] * keep[:, None, :]
        g = g * keep
        diag = np.einsum("nkk->nk", h)
        damp = lam[rows, None] * (diag + 1e-12 * diag.max(axis=1, keepdims=True)) + frozen + 1e-300
        a = h + np.einsum("nk,kl->nkl", damp, np.eye(k))
        if linear is None:
            step = -linalg.solve_spd(a, g)
        else:  # the plane's normal as a second right-hand side (`_on_plane`)
            both = linalg.solve_spd(a, np.stack([g, linear[0][None, :] * keep], axis=2))
            step = -both[..., 0]
        step = np.nan_to_num(step) * keep
        if linear is not None:
            step = _on_plane(linear, a, g, np.nan_to_num(both[..., 1]), zr, step, keep, lo, hi)
        if acceleration:
            step = _accelerated(problem, rows, zr, r[rows], j, a, step, keep, lo, hi)
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


def _accelerated(problem, rows, z, r, j, a, step, keep, lo, hi):
    """The steps v + a / 2 of Transtrum & Sethna (module docstring), a from the damped
    normal matrix a (N, k, k) already formed; the plain step v where the acceleration is
    too large to trust. One residual call at z + h v."""
    probe = problem.residuals(np.clip(z + GEODESIC_PROBE * step, lo, hi), rows)
    along = np.einsum("nmk,nk->nm", j, step)
    second = (2.0 / GEODESIC_PROBE) * ((probe - r) / GEODESIC_PROBE - along)
    acc = np.nan_to_num(-linalg.solve_spd(a, np.einsum("nmk,nm->nk", j, second))) * keep
    trusted = 2.0 * np.sqrt(linalg.dot(acc, acc)) <= GEODESIC_RATIO * np.sqrt(linalg.dot(step, step))
    return step + 0.5 * acc * trusted[:, None]


def _on_plane(linear, m, g, u, z, step, keep, lo, hi) -> np.ndarray:
    """Steps (N, k) from rows z that would cross the plane of the linear constraint
    c.z <= b (`linear` = (c, b)) replaced by the model's minimizer on it: with M the damped
    normal matrix (N, k, k), g the gradient and u = M^-1 c (the frozen variables, not
    `keep`, held), s' = s + u (b - c.z - c.s) / (c.u). Where that takes a variable of the
    plane out of the box, the variable is held at its bound and the minimizer on the plane
    taken again among the others (an active set that only grows): the plane is met and
    the box kept."""
    c, b = linear
    cm = c[None, :] * keep
    over = np.flatnonzero(np.einsum("nk,nk->n", cm, z + step) > b)
    if not len(over):
        return step
    step = step.copy()
    held = ~keep[over]
    fixed = np.zeros((len(over), z.shape[1]))  # the held variables' steps
    m, g, z_o, u = m[over], g[over], z[over], u[over]
    s_o = step[over]
    for _ in range(z.shape[1]):
        cu = np.einsum("nk,nk->n", cm[over], u)
        gap = b - np.einsum("nk,k->n", z_o + s_o, c)
        s_o = s_o + np.where(cu > 0.0, gap / np.where(cu > 0.0, cu, 1.0), 0.0)[:, None] * u
        out = ~held & (c[None, :] != 0.0) & ((z_o + s_o < lo) | (z_o + s_o > hi))
        if not out.any():
            break
        held |= out  # at the bound it crossed; the rest solved again with these held
        fixed = np.where(out, np.clip(z_o + s_o, lo, hi) - z_o, fixed)
        free = ~held
        a = linalg.restricted(m, free)
        rhs = np.where(free, -(g + np.einsum("nkl,nl->nk", m, fixed)), fixed)
        both = np.nan_to_num(linalg.solve_spd(a, np.stack([rhs, c[None, :] * free], axis=2)))
        s_o, u = both[..., 0], both[..., 1]
    step[over] = s_o
    return step
