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
             gain: float = 1e-12, acceleration: bool = False):
    """Levenberg-Marquardt on every row of z at once, leaving `reserve` evaluations of the
    budget unspent (a Jacobian costs 2k + 1 per row), and stopping every row once one
    costs `enough` or less; with geodesic `acceleration` (dense Jacobians; see the module
    docstring); returns (z, cost, converged): a row has converged when a step
    gains less than `gain` of its cost, when no step gains anything (damping above 1e10),
    or at an exact fit."""
    z = z.copy()
    k = z.shape[1]
    if k == 0 or problem.budget.left - reserve < len(z):
        return z, np.full(len(z), np.inf), np.zeros(len(z), dtype=bool)
    r = problem.residuals(z, slice(None))
    f = np.einsum("ij,ij->i", r, r)
    lam = np.full(len(z), 1e-3)
    jac = None  # each row's Jacobian at its point: (N, m, k), or structured (`_structured_step`)
    stale = np.ones(len(z), dtype=bool)  # Jacobian to (re)compute
    active = np.ones(len(z), dtype=bool)
    lo, hi = problem.lo, problem.hi
    linear = getattr(problem, "linear", None)
    for _ in range(iterations):
        rows = np.flatnonzero(active)
        if len(rows) == 0 or f.min() <= enough or problem.budget.left - reserve < len(rows) * (2 * k + 1):
            break
        need = rows[stale[rows]]
        if len(need):
            jac = _stored(jac, need, problem.jacobian(z[need], need, r[need]), len(z))
            stale[need] = False
        zr = z[rows]
        if not isinstance(jac, np.ndarray):  # structured: an arrow's normal equations, in O(n)
            step = _structured_step(jac.take(rows), r[rows], zr, lam[rows], lo, hi, linear)
        else:
            j = jac[rows]
            g = np.einsum("nmk,nm->nk", j, r[rows])
            jt = np.ascontiguousarray(np.transpose(j, (0, 2, 1)))  # rows of J^T: einsum's fast loop
            h = np.einsum("nkm,nlm->nkl", jt, jt)
            frozen = _frozen(zr, g, lo, hi)
            keep = ~frozen
            h = h * keep[:, :, None] * keep[:, None, :]
            g = g * keep
            a = h + np.einsum("nk,kl->nkl", _damping(np.einsum("nkk->nk", h), lam[rows], frozen), np.eye(k))
            if linear is None:
                step = -linalg.solve_spd(a, g)
            else:  # the plane's normal as a second right-hand side (`_on_plane`)
                both = linalg.solve_spd(a, np.stack([g, linear[0][None, :] * keep], axis=2))
                step = -both[..., 0]
            step = np.nan_to_num(step) * keep
            if linear is not None:
                step = _on_plane(linear, Dense(a), g, np.nan_to_num(both[..., 1]), zr, step, keep, lo, hi)
            if acceleration:
                step = _accelerated(problem, rows, zr, r[rows], j, a, step, keep, lo, hi)
        znew = np.clip(zr + step, lo, hi)
        rnew = problem.residuals(znew, rows)
        fnew = np.einsum("ij,ij->i", rnew, rnew)
        ok = fnew < f[rows]
        acc = rows[ok]
        small = ok & (f[rows] - fnew <= gain * f[rows])
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


def _damping(diag, lam, frozen) -> np.ndarray:
    """Marquardt's damping lambda D, D = diag(J^T J) (plus a trace of its largest entry, so
    that a zero column is damped too); 1 on a frozen variable, which then stays put."""
    return lam[:, None] * (diag + 1e-12 * diag.max(axis=1, keepdims=True)) + frozen + 1e-300


def _structured_step(j, r, z, lam, lo, hi, linear) -> np.ndarray:
    """The damped Gauss-Newton steps of rows z whose Jacobians j have a structure of their
    own (linkcli.search.arrow, linkcli.search.increments: their `normal` solves the damped
    system in O(n)); with the plane of a linear constraint, as the dense steps."""
    g = j.gradient(r)
    frozen = _frozen(z, g, lo, hi)
    keep = ~frozen
    g = g * keep
    normal = j.normal(keep)
    damp = _damping(normal.diagonal(), lam, frozen)
    if linear is None:
        return np.nan_to_num(-normal.solve(damp, g)) * keep
    both = normal.solve(damp, np.stack([g, linear[0][None, :] * keep], axis=2))
    step = np.nan_to_num(-both[..., 0]) * keep
    return _on_plane(linear, Structured(j, keep, damp), g, np.nan_to_num(both[..., 1]), z, step, keep, lo, hi)


class Dense:
    """The damped normal matrices m (N, k, k) of `_on_plane`: restricted solves and products."""

    def __init__(self, m: np.ndarray) -> None:
        self.m = m

    def take(self, rows) -> Dense:
        return Dense(self.m[rows])

    def solve_held(self, free: np.ndarray, rhs: np.ndarray) -> np.ndarray:
        """The system with the unknowns not `free` held at their right-hand side."""
        return linalg.solve_spd(linalg.restricted(self.m, free), rhs)

    def times(self, x: np.ndarray) -> np.ndarray:
        return np.einsum("nkl,nl->nk", self.m, x)


class Structured:
    """As `Dense` for Jacobians j with a structure of their own, the unknowns `keep` and
    the damping `damp` of the step."""

    def __init__(self, j, keep: np.ndarray, damp: np.ndarray) -> None:
        self.j, self.keep, self.damp = j, keep, damp

    def take(self, rows) -> Structured:
        return Structured(self.j.take(rows), self.keep[rows], self.damp[rows])

    def solve_held(self, free: np.ndarray, rhs: np.ndarray) -> np.ndarray:
        return self.j.normal(free).solve(np.where(free, self.damp, 1.0), rhs)

    def times(self, x: np.ndarray) -> np.ndarray:
        return self.j.normal(self.keep).matvec(self.damp, x)


def _frozen(z, g, lo, hi) -> np.ndarray:
    """The variables at a bound whose gradient pushes out of the box."""
    return (((z <= lo + 1e-12 * (np.abs(lo) + 1)) & (g > 0))
            | ((z >= hi - 1e-12 * (np.abs(hi) + 1)) & (g < 0)))


def _stored(jac, rows, new, size: int):
    """The batch's Jacobians with those of `rows` replaced by `new` (dense (N, m, k), or
    structured: an `Arrow`, `Increments`), the store made on first use."""
    if jac is None:
        jac = np.zeros((size,) + new.shape[1:]) if isinstance(new, np.ndarray) else type(new).empty(size, new)
    if not isinstance(jac, np.ndarray):
        jac.put(rows, new)
    else:
        jac[rows] = new
    return jac


def _on_plane(linear, system, g, u, z, step, keep, lo, hi) -> np.ndarray:
    """Steps (N, k) from rows z that would cross the plane of the linear constraint
    c.z <= b (`linear` = (c, b)) replaced by the model's minimizer on it: with M the damped
    normal matrix (`system`: Dense or Structured), g the gradient and u = M^-1 c (the frozen
    variables, not `keep`, held), s' = s + u (b - c.z - c.s) / (c.u). Where that takes a variable of the
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
    system, g, z_o, u = system.take(over), g[over], z[over], u[over]
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
        rhs = np.where(free, -(g + system.times(fixed)), fixed)
        both = np.nan_to_num(system.solve_held(free, np.stack([rhs, c[None, :] * free], axis=2)))
        s_o, u = both[..., 0], both[..., 1]
    step[over] = s_o
    return step
