"""Search machinery for path generation, vectorized over candidates (numpy; scipy lazily).

The objective evaluations (one per candidate evaluated, every finite-difference column
included; a closed-form Jacobian counts CLOSED_FORM, one more with the penalties'
differences) are counted by `linkcli.search.budget.Budget` against the `[solver] budget`.
* `Space`: the free variables of a Design, optionally with the coupler point and the
  ground pivot projected out (solved by `starts.fit_linear` at every evaluation:
  variable projection, which leaves the lengths, the angles and the timing to search);
  residuals and Jacobians of many candidates as one batch: the target errors' slopes in
  closed form (`derivatives`), the penalties' in closed form or by central differences;
  free timing's sweep, sum(delta) <= 2 pi, as the linear constraint the
  Levenberg-Marquardt holds on its plane (a penalty alone made the search crawl along
  it: closed curves end at a sweep of one turn).
* `distinct`: the best candidates, pairwise apart (restarts from distinct basins).
* `batch_lm`: Levenberg-Marquardt on many candidates at once
  (linkcli.search.levenberg_marquardt), each row with its own branch sign and direction;
  a Jacobian reuses the closure and linear fit of the residual call that evaluated
  its point (`Fixed`).
* `polish`: `batch_lm` on one candidate (it was scipy's least_squares, whose SVD follows
  the BLAS kernel: one machine ended on another member of a continuum of exact fits).
* `settle`: the final Newton-KKT polish on the constraints that bind (linkcli.search.kkt).
* `differential_evolution`: linkcli.search.evolution's, on the penalized sum of squares.

Every linear system is solved by `linkcli.search.linalg` (no BLAS): the whole search takes
the same steps under every BLAS kernel.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.search import levenberg_marquardt, sampling
from linkcli.search.budget import Budget
from linkcli.search.evolution import evolve
from linkcli.search.increments import Increments
from linkcli.types.path_generation import derivatives
from linkcli.types.path_generation.derivatives import LINEAR
from linkcli.types.path_generation.model import N_LINK, Design
from linkcli.types.path_generation.starts import fit_linear

POLISH_ITERATIONS = 100  # Levenberg-Marquardt steps of one polish, at most
DE_TOL = 1e-8  # differential evolution stops when the costs' spread is this small
SETTLE_STEP = 3e-5  # unit box: the final polish's difference step (kkt.slopes). Path optima
# lie in flat valleys that turn a slope's truncation error (~ step^4) into a shift of the
# optimum: at 1e-4 closed18_timed's ground moves in the 6th digit, at 3e-5 in the 8th, while
# the round-off left (~ eps / step) keeps seeds within 1e-9 of each other
CURVATURE_STEP = 1e-4  # unit box: differences of the closed-form gradient for the settle's Hessian
# of the Lagrangian (kkt, `curvature`), as motion generation's
NONLINEAR = 0.01  # a Jacobian column whose second difference exceeds this share of the first
SHRINK = 16  # is taken again with a step this much smaller,
SHRINKS = 3  # at most this many times
MIN_ROOM = 1e-3  # a central step shrunk below this share of the usual one is round-off
ROUND_OFF = 1e-13  # dimensionless residual differences this small are round-off
INCREMENTS_TARGETS = 40  # free timing with this many targets or more: the field's Jacobians as
# linkcli.search.increments factors, O(n) a step (fewer: dense, O(n^3), the bits of before).
# Measured, a step of 96 rows (Jacobian and solve): 32 targets dense 27 ms, factors 39 ms;
# 48: 55 and 38 ms; 96: 311 and 106 ms; 192: 2252 and 114 ms
CLOSED_FORM = 2  # evaluations a row's closed-form Jacobian counts (measured: 1.8 to 2.9 times a
# residual evaluation's time for 4 to 15 variables, the penalties' slopes included)


class Space:
    """The free variables of a Design: z (N, k) <-> full x (N, nx), with the per-candidate
    branch sign and turning direction, and a counted residual function."""

    def __init__(self, design: Design, budget: Budget, project: bool = False,
                 closed_penalties: bool | None = None) -> None:
        self.design = design
        self.budget = budget
        self.project = project  # variable projection: coupler point and pivot by fit_linear
        self.closed_penalties = project if closed_penalties is None else closed_penalties
        free = design.free.copy()
        if project:
            free[LINEAR] = False
        self.idx = np.flatnonzero(free)
        self.lo = design.lo[self.idx]
        self.hi = design.hi[self.idx]
        self.base = np.where(free, 0.0, 0.5 * (design.lo + design.hi))
        self.linear = None  # free timing: the sweep sum(delta) <= 2 pi, held by the LM exactly
        if design.timing == "free" and np.any(self.idx > N_LINK):
            self.linear = ((self.idx > N_LINK).astype(float), 2.0 * math.pi)
        # many targets, free timing, the field stage: Jacobians as increments' factors
        self.increments = (project and self.closed_penalties and design.timing == "free"
                           and design.n_targets >= INCREMENTS_TARGETS
                           and int(np.sum(self.idx >= N_LINK)) == design.n_targets)

    @property
    def k(self) -> int:
        return len(self.idx)

    def full(self, z: np.ndarray, sign=None, s=None) -> np.ndarray:
        """Full vectors; with projection (and sign, s given), the linear part fitted."""
        x = np.repeat(self.base[None, :], len(z), axis=0)
        x[:, self.idx] = z
        if self.project and sign is not None:
            x = fit_linear(self.design, x, sign, s)
        return x

    def free(self, x: np.ndarray) -> np.ndarray:
        return x[:, self.idx]

    def fitted(self, z, sign, s):
        """Full vectors of rows z (the linear part fitted when projected) and their closure."""
        if self.project:
            return fit_linear(self.design, self.full(z), sign, s, with_pose=True)
        x = self.full(z)
        return x, self.design.frame(x, sign, s)[0]

    def residuals(self, z, sign, s, weight, fit=None) -> np.ndarray:
        """Counted residuals of rows z (`fit`: their `fitted`, when the caller has it)."""
        self.budget.add(len(z))
        x, pose = self.fitted(z, sign, s) if fit is None else fit
        return self.design.residuals(x, sign, s, weight, pose=pose)

    def cost(self, z, sign, s, weight) -> np.ndarray:
        r = self.residuals(z, sign, s, weight)
        return np.einsum("ij,ij->i", r, r)

    def step_sizes(self, z: np.ndarray) -> np.ndarray:
        """Central-difference half steps (N, k): about eps^(1/3) of each variable's scale,
        shrunk where a bound is nearer than that (the shifted points stay inside), down
        to MIN_ROOM of it; 0 nearer still (`_differences` then steps away from the bound:
        a step shrunk to round-off, 7e-15 below a bound, gave slopes wrong in the first
        digit)."""
        width = np.where(np.isfinite(self.hi - self.lo), self.hi - self.lo, 1.0)
        h = 6e-6 * np.maximum(np.abs(z), np.maximum(width[None, :] * 1e-2, 1e-3))
        room = np.minimum(z - self.lo, self.hi - z)
        return np.where(room >= h, h, np.where(room >= MIN_ROOM * h, room, 0.0))

    def jacobian(self, z, sign, s, weight, r0, fit=None):
        """(N, m, k) Jacobians of the residuals r0 (N, m) at rows z (`fit`: their
        `fitted`, when the caller has it): the target errors' slopes in closed form
        (`derivatives`, projected or on every variable; counted as CLOSED_FORM evaluations
        a row); the penalties' in closed form too with `closed_penalties` (the field
        stage), else by differences of `Design.penalty_residuals` (which need no coupler
        point; one evaluation a row) made faithful by `_sharpened`; every slope by
        differences on a row where the closed form does not hold (no assembly, a dead
        point). The sweep's penalty (free timing), which the Levenberg-Marquardt holds
        as a linear constraint (`linear`), has no slope where it is met."""
        n, k = z.shape
        design = self.design
        self.budget.add(CLOSED_FORM * n)
        x, frame = self.fitted(z, sign, s) if fit is None else fit
        if self.increments:
            return self._increments(x, frame, sign, s, weight, r0)
        if self.project:
            slopes, ok = derivatives.projected_jacobian(design, self.idx, x, frame, sign, s)
        else:
            slopes, ok = derivatives.full_jacobian(design, self.idx, x, frame, s)
        m = slopes.shape[1]
        jac = np.empty(r0.shape + (k,))
        jac[:, :m] = slopes
        if r0.shape[1] > m and self.closed_penalties:  # violated: the penalties r0 shows positive
            violated = r0[:, m:] > 0.0
            jac[:, m:] = 0.0
            some = np.flatnonzero(violated.any(axis=1))  # the rows with a constraint to slope
            if len(some):
                jac[some, m:] = derivatives.penalty_jacobian(design, self.idx, x[some], frame.take(some),
                                                             s[some], weight, violated[some])
        elif r0.shape[1] > m:  # differences: where a constraint binds, `_sharpened`'s slopes
            # on the violated side of a kink settle it (closed-form slopes, 0 on the
            # feasible side, left arc6_window's seeds crawling along its window edge)
            self.budget.add(n)

            def penalties(zz, rows):
                return design.penalty_residuals(self.full(zz), s[rows], weight)

            jac[:, m:] = self._differences(z, r0[:, m:], penalties, 0)
        bad = np.flatnonzero(~ok)
        if len(bad):
            jac[bad] = self._differences(z[bad], r0[bad], self._shifted(sign[bad], s[bad], weight),
                                         None if self.project else m)
        if self.linear is not None and r0.shape[1] > m:  # the sweep's penalty (the last): the
            # LM holds it, so no slope where it is met (differences across its kink mislead)
            jac[:, -1] = np.where(r0[:, -1:] > 0.0, jac[:, -1], 0.0)
        return jac

    def _increments(self, x, frame, sign, s, weight, r0) -> Increments:
        """The field's Jacobians as linkcli.search.increments factors (free timing, many
        targets): the target errors' (`derivatives.increments_parts`) and the penalties'
        (`penalty_jacobian` along the links, `penalty_angle_parts` along each target's
        angle) slopes in closed form; a row where the closed form fails (no assembly or a
        dead point at a target) keeps only its penalties' slopes, which lead it back (the
        dense stage takes differences there: their rows would not be O(n))."""
        design = self.design
        n_rows, n = len(x), design.n_targets
        m_t = 2 * n
        link = self.idx[self.idx < N_LINK]
        w, local, a, coef, ok = derivatives.increments_parts(design, self.idx, x, frame, sign, s)
        bad = ~ok  # no assembly or a dead point at a target: its slopes are not the toggle's
        w[bad], local[bad], coef[bad] = 0.0, 0.0, 0.0
        violated = r0[:, m_t:] > 0.0
        w_pen = derivatives.penalty_jacobian(design, link, x, frame, s, weight, violated)
        local_pen, spread = derivatives.penalty_angle_parts(design, x, frame, s, weight, violated)
        lead = violated.shape[1] - n - 2 - 1  # Grashof and window rows before the assembly's
        owner = np.concatenate([np.repeat(np.arange(n), 2), np.full(violated.shape[1], -1)])
        owner[m_t + lead:m_t + lead + n] = np.arange(n)
        f = np.zeros((n_rows, r0.shape[1], 4 + len(spread)))
        f[:, :m_t, :4] = -a
        for i, (row, _) in enumerate(spread):
            f[:, m_t + row, 4 + i] = 1.0
        h = np.concatenate([coef] + [slope[:, None, :] for _, slope in spread], axis=1)
        e = np.ones((n_rows, n))
        e[:, 1:] = s[:, None]
        return Increments(np.nan_to_num(np.concatenate([w, w_pen], axis=1)),
                          np.nan_to_num(np.concatenate([local, local_pen], axis=1)), owner,
                          np.nan_to_num(f), np.nan_to_num(h), e)

    def _shifted(self, sign, s, weight):
        """The counted residuals of shifted copies of rows (`rows`: each copy's row)."""
        return lambda zz, rows: self.residuals(zz, sign[rows], s[rows], weight)

    def _differences(self, z, r0, evaluate, smooth=None):
        """(N, m, k) slopes of `evaluate(zz, rows)` (residuals of the points zz, shifted
        copies of the rows `rows` of z) by central differences (one-sided, second order,
        where a variable is nearer a bound than its step), the N * 2k shifted points as
        one batch; made faithful by `_sharpened` where the step misleads when `smooth` is
        given (how many leading residuals are smooth wherever the linkage assembles)."""
        n, k = z.shape
        h = self.step_sizes(z)
        width = np.where(np.isfinite(self.hi - self.lo), self.hi - self.lo, 1.0)
        edge = h <= 0.0
        h = np.where(edge, 6e-6 * np.maximum(np.abs(z), np.maximum(width[None, :] * 1e-2, 1e-3)), h)
        # at a bound: forward (or backward) three-point formula inside the box
        sgn = np.where(z - self.lo <= self.hi - z, 1.0, -1.0)
        off1 = np.where(edge, sgn * h, h)
        off2 = np.where(edge, 2 * sgn * h, -h)
        zz = np.repeat(z[:, None, :], 2 * k, axis=1)
        zz[:, np.arange(k), np.arange(k)] += off1
        zz[:, k + np.arange(k), np.arange(k)] += off2
        rr = evaluate(zz.reshape(n * 2 * k, k), np.repeat(np.arange(n), 2 * k))
        rr = rr.reshape(n, 2 * k, -1)
        r1, r2 = rr[:, :k], rr[:, k:]
        central = (r1 - r2) / (2 * h[:, :, None])
        if smooth is not None:
            central = self._sharpened(z, evaluate, smooth, r0, r1, r2, h, edge, central)
        onesided = (4 * r1 - r2 - 3 * r0[:, None, :]) / (2 * (sgn * h)[:, :, None])
        return np.transpose(np.where(edge[:, :, None], onesided, central), (0, 2, 1))

    def _sharpened(self, z, evaluate, fit, r0, r1, r2, h, edge, central):
        """The central-difference columns (N, k, m) made faithful where a step of the usual
        size misleads: a column whose second difference exceeds NONLINEAR of its first
        (the step spans a bend smaller than itself: a target next to a dead point, where
        the coupler moves like the square root of the distance to it) is taken again
        with a step SHRINK smaller, at most SHRINKS times; and a violated constraint's
        penalty (nonzero here) that vanishes on one side of the step gets the slope on
        this side of its kink, not half of it (the search would crawl along the active
        constraint). A penalty max(0, g) that is 0 at one of the three points is left
        out of the bend test: no smaller step resolves a kink. The first `fit` residuals
        (target errors) are smooth wherever the linkage assembles."""
        k = z.shape[1]
        h = h.copy()
        t0 = r0[:, None, :]
        noise = ROUND_OFF * (1.0 + _spread(r0))[:, None]
        for _ in range(SHRINKS):
            smooth = (r1 != 0.0) & (r2 != 0.0) & (t0 != 0.0)
            smooth[:, :, :fit] = True
            bend = _spread(np.where(smooth, r1 - 2.0 * t0 + r2, 0.0))
            curved = ~edge & (bend > NONLINEAR * _spread(np.where(smooth, r1 - r2, 0.0)) + noise)
            if not curved.any():
                break
            rows, cols = np.nonzero(curved)
            h[rows, cols] /= SHRINK
            zs = np.repeat(z[rows][:, None, :], 2, axis=1)
            zs[np.arange(len(rows)), 0, cols] += h[rows, cols]
            zs[np.arange(len(rows)), 1, cols] -= h[rows, cols]
            rs = evaluate(zs.reshape(-1, k), np.repeat(rows, 2))
            rs = rs.reshape(len(rows), 2, -1)
            r1, r2, central = r1.copy(), r2.copy(), central.copy()
            r1[rows, cols], r2[rows, cols] = rs[:, 0], rs[:, 1]
            central[rows, cols] = (rs[:, 0] - rs[:, 1]) / (2 * h[rows, cols][:, None])
        hh = h[:, :, None]
        central = np.where((t0 != 0.0) & (r2 == 0.0) & (r1 != 0.0), (r1 - t0) / hh, central)
        return np.where((t0 != 0.0) & (r1 == 0.0) & (r2 != 0.0), (t0 - r2) / hh, central)


def _spread(d: np.ndarray) -> np.ndarray:
    """max |d| over the last axis (the residuals)."""
    return np.max(np.abs(d), axis=-1)


# ---------------------------------------------------------------- selection

def distinct(z: np.ndarray, cost: np.ndarray, width: np.ndarray, k: int, tol: float = 1e-3):
    """Indices of up to k lowest-cost finite rows, each more than `tol` (relative to the
    bounds' widths, max norm) away from every row already taken."""
    order = np.argsort(cost, kind="stable")
    order = order[np.isfinite(cost[order])]
    if z.shape[1] == 0:
        return order[:1]
    w = np.where(np.isfinite(width) & (width > 0), width, 1.0)
    return np.array(sampling.distinct(z / w, order, tol, k), dtype=int)


# ---------------------------------------------------------------- Levenberg-Marquardt

class Fixed:
    """The Space's residuals with each row's branch sign and turning direction and the
    penalty weight held fixed: the batch of least-squares problems in a box that
    linkcli.search.levenberg_marquardt solves."""

    def __init__(self, space: Space, sign, s, weight: float) -> None:
        self.space, self.sign, self.s, self.weight = space, sign, s, weight
        self.lo, self.hi, self.budget, self.linear = space.lo, space.hi, space.budget, space.linear
        self.last = None  # the last residual call's rows, points and fit

    def residuals(self, z, rows) -> np.ndarray:
        sign, s = self.sign[rows], self.s[rows]
        fit = self.space.fitted(z, sign, s)
        self.last = (np.arange(len(self.sign))[rows], z, fit)
        return self.space.residuals(z, sign, s, self.weight, fit=fit)

    def jacobian(self, z, rows, r0) -> np.ndarray:
        return self.space.jacobian(z, self.sign[rows], self.s[rows], self.weight, r0,
                                   fit=self._kept(z, rows))

    def _kept(self, z, rows):
        """The fit (`Space.fitted`) of rows z from the last residual call, when it held
        them at these very points (Levenberg-Marquardt takes the Jacobians of the points
        it has just accepted), else None."""
        if self.last is None:
            return None
        held, zz, (x, frame) = self.last
        pos = np.minimum(np.searchsorted(held, rows), len(held) - 1)
        if not (np.array_equal(held[pos], rows) and np.array_equal(zz[pos], z)):
            return None
        return x[pos], frame.take(pos)


def batch_lm(space: Space, z, sign, s, weight: float, iterations: int, reserve: int = 0,
             enough: float = -1.0):
    """linkcli.search.levenberg_marquardt.batch_lm on the rows z (N, k) with their signs
    and directions (N,): returns (z, cost, converged)."""
    return levenberg_marquardt.batch_lm(Fixed(space, sign, s, weight), z, iterations, reserve, enough)


# ---------------------------------------------------------------- polish

def polish(space: Space, z0, sign: float, s: float, weight: float, max_nfev: int):
    """Levenberg-Marquardt (`batch_lm`, one row) on every free variable from z0 (k,),
    within max_nfev evaluations and POLISH_ITERATIONS steps. Returns (z, cost, converged).
    BLAS-free like every step of the search, so that the end point (one of a continuum
    of exact fits, say) does not follow the machine's BLAS kernel."""
    z0 = np.clip(np.asarray(z0, dtype=float), space.lo, space.hi)
    if not np.all(np.isfinite(z0)) or not np.all(space.lo <= space.hi):
        return z0, math.inf, False
    reserve = max(0, space.budget.left - max_nfev)
    z, f, done = batch_lm(space, z0[None, :], np.array([sign]), np.array([s]), weight,
                          POLISH_ITERATIONS, reserve=reserve)
    return z[0], float(f[0]), bool(done[0])


# ---------------------------------------------------------------- final polish

def settle(space: Space, z0, sign: float, s: float):
    """Newton on the KKT system of the constraints that bind at z0 (linkcli.search.kkt),
    on the objective sum |P_k - T_k|^2 / L^2 (no penalty), in the unit box of the free
    variables, slopes by `kkt.slopes`; constraints c = -g / L from `Design.constraints`
    (g <= 0 feasible). The Hessian model is Gauss-Newton's 2 J^T J; with prescribed timing
    kkt's differenced Hessian of the Lagrangian where its steps shrink only linearly or
    grow (`curvature="stalled"`): an approximate path leaves residuals whose own curvature
    Gauss-Newton misses (tuning case 80 of benchmarks/constrained_variants.py: its steps
    grew 2.4 times a step, every settle failed after its 30 steps and they took half the
    run; now 0.82 s against 1.43). Only there: the constraints' curvature added at every
    step (`curvature=True`) spent a round pick's settle budget (PICK_SETTLE) on Grashof
    inequalities, which are linear, and the pick stayed unsettled. Not with free timing:
    its input angles are a start plus cumulative increments, every one moving the later
    targets, so the differenced Hessian costs 2 k gradients of k = 9 + n variables and a
    round's pick ran out of its settle's evaluations (tuning case 73: 2 of 5 seeds lost
    their confirmation). Returns the kkt.Settled record with z in place of the unit
    coordinates."""
    from linkcli.search import kkt
    design = space.design
    width = space.hi - space.lo
    m = 2 * design.n_targets

    def values(u):  # (N, k) unit points -> (N, 2n + constraints): residuals, constraints
        space.budget.spend(len(u))  # BudgetSpent beyond the cap
        x = space.full(space.lo + np.clip(u, 0.0, 1.0) * width)
        pts, pose, phi = design.points(x, np.full(len(u), sign), np.full(len(u), s))
        r = (pts - design.targets[None]).reshape(len(u), -1) / design.scale
        return np.concatenate([r, -design.constraints(x, pose, phi) / design.scale], axis=1)

    def points(us, gauss_newton: bool):  # kkt.Points of unit points us (K, k): one batch of values;
        # the Gauss-Newton matrix only where Newton steps from them (not at the differenced Hessian's)
        v, jac = kkt.slopes_many(values, us, step=SETTLE_STEP)
        jr = _exact_slopes(space, us, sign, s, width, jac[:, :m])
        return kkt.least_squares_points(v, jac, m, gauss_newton, jr)

    def evaluate(u):
        return points(np.asarray(u, float)[None, :], True)[0]

    u0 = np.clip((np.asarray(z0, dtype=float) - space.lo) / np.where(width > 0, width, 1.0), 0.0, 1.0)
    curvature = "stalled" if design.timing == "prescribed" else False
    out = kkt.settle(evaluate, u0, hessian_step=CURVATURE_STEP, curvature=curvature,
                     evaluate_many=lambda us: points(us, False))
    out.u = space.lo + out.u * width
    return out


def _exact_slopes(space: Space, us, sign: float, s: float, width, differenced: np.ndarray) -> np.ndarray:
    """The target errors' slopes (K, 2n, k) at the unit points us (K, k) in closed form
    (derivatives.full_jacobian, times the box's width), where they hold; else the
    differenced ones (K, 2n, k). A difference's truncation error (~ step^4) moves a flat
    valley's optimum in the 7th digit, by an amount that follows the machine's last bits
    (lin10_closed with numpy's vector paths narrowed); closed-form slopes leave round-off alone."""
    x = space.full(space.lo + np.clip(us, 0.0, 1.0) * width)
    signs, dirs = np.full(len(us), sign), np.full(len(us), s)
    _, pose, _ = space.design.points(x, signs, dirs)
    jac, ok = derivatives.full_jacobian(space.design, space.idx, x, pose, dirs)
    return np.where(ok[:, None, None], jac * width, differenced)


# ---------------------------------------------------------------- differential evolution

def differential_evolution(space: Space, rng_seed: int, weight: float, budget: int):
    """Differential evolution (linkcli.search.evolution) on the penalized sum of
    squares; a branch "either" or direction "either" becomes one more variable in [-1, 1]
    whose sign picks it. Returns (z, sign, s, cost, converged): converged when the
    population's spread of costs fell below DE_TOL of their mean (scipy's criterion)."""
    design = space.design
    k = space.k
    pick_branch = design.branch == "either"
    pick_dir = design.timing == "free" and design.direction == "either"
    extra = int(pick_branch) + int(pick_dir)
    bounds = list(zip(space.lo, space.hi)) + [(-1.0, 1.0)] * extra
    fixed_sign = -1.0 if design.branch == "open" else 1.0
    fixed_s = -1.0 if design.direction == "cw" else 1.0

    def decode(rows):  # rows (S, k + extra)
        z = rows[:, :k]
        col = k
        sign = np.full(len(z), fixed_sign)
        s = np.full(len(z), fixed_s)
        if pick_branch:
            sign = np.where(rows[:, col] < 0, -1.0, 1.0)
            col += 1
        if pick_dir:
            s = np.where(rows[:, col] < 0, -1.0, 1.0)
        return z, sign, s

    def cost(rows):
        z, sign, s = decode(rows)
        return space.cost(z, sign, s, weight)

    dims = k + extra
    popsize = max(1, min(15, budget // max(1, 2 * dims)))
    npop = popsize * dims
    if npop < 5 or npop > budget:  # too small a budget for a population: random draws
        v = np.array([lo for lo, _ in bounds]) + np.array([hi - lo for lo, hi in bounds]) * \
            np.random.default_rng(rng_seed).random((max(1, budget), dims))
        costs = cost(v)
        i = int(np.argmin(costs))
        z, sign, s = decode(v[i][None, :])
        return z[0], float(sign[0]), float(s[0]), float(costs[i]), False
    maxiter = max(0, budget // npop - 1)
    out = evolve(cost, bounds, maxiter, init="latinhypercube", seed=rng_seed, popsize=popsize, tol=DE_TOL,
                 mutation=(0.5, 1.0), recombination=0.7)
    z, sign, s = decode(out.x[None, :])
    return z[0], float(sign[0]), float(s[0]), out.cost, out.converged
