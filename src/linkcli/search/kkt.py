"""The last step of every search: Newton on the KKT system of the active set, to machine
precision, so that the printed digits are the optimum's and not the path's.

    minimize f(u)  subject to  c(u) >= 0,  0 <= u <= 1

A search (differential evolution, SLSQP, Levenberg-Marquardt with penalties) stops where
its own tolerances let it: at 1e-8 of a binding constraint, or part way along a flat
valley, at a point that differs in the 6th digit from one machine to another. At such a
point the binding set is known: the constraints with c_i <= ACTIVE and the variables at a
bound. Held as equalities (the variables at bounds fixed there), the optimum is a root of

    g(u) - A(u)^T lambda = 0,   c_A(u) = 0          (g = grad f, A = dc_A/du)

and Newton's method on it (Nocedal & Wright, Numerical Optimization, 2nd ed., 2006,
section 18.1, the Newton-KKT / SQP step with an equality-constrained QP)

    [ H  -A^T ] [ s      ]   [ -g   ]
    [ A   0   ] [ lambda ] = [ -c_A ]

converges quadratically (H the Hessian of the Lagrangian; the Gauss-Newton matrix
2 J^T J for least squares), to round-off of the KKT residual. A multiplier of the wrong
sign (lambda_i < 0: the constraint does not bind) or an inactive constraint that the step
breaks changes the active set, and Newton starts again (at most ROUNDS times); a round that
would begin again from the same point on the same binding set (a failed round releases a bound
its next round meets again) ends the settle instead: it would end as it did. The linear
algebra is `linalg` (no BLAS): the same steps on every machine.

A step that would cross the box is stopped where its first variable meets its bound (the
ratio test, `_to_bound`), and the next round holds that variable there: clipped instead,
a long step along a flat valley is no longer Newton's, and its line search stalls short of
an optimum on the bound. Where Gauss-Newton's steps shrink by less than STALLED a step (a
large residual's curvature that 2 J^T J misses), its model is corrected along the steps
taken by symmetric rank-one secant updates (`_secant`), at no evaluation's cost. The
corrected model need not stay positive definite (Nocedal & Wright, sec. 6.2): where its step
finds no lower merit in HALVINGS halvings, the correction is dropped and Newton goes on from
the same iterate on Gauss-Newton's model (failing there, the pass went back to its start:
picks far along closed18_free's crank-rocker edge, in its optimum's basin, never settled).

A Newton pass also ends, converged, at the first iterate where its model has only round-off
of f left to gain (`_at_round_off`: a step within PRINTED whose slope and curvature terms
are below ROUND_OFF |f|), when its steps never fall below the step tolerance: in a flat
valley the slopes' round-off over a small eigenvalue of the Hessian keeps them above it.
A settle that fails far from a KKT point is the caller's to mend (motion generation walks
there first with linkcli.search.polish's constrained Levenberg-Marquardt).

The end point is only offered: the caller keeps it when it is at least as good under its
own ranking (`settle` returns it with its f and worst violation).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from linkcli.search import linalg

ACTIVE = 1e-7  # a constraint this close to 0 (its own scale, order one) binds at the start
SLOPE_STEP = 3e-4  # unit box: the step of `slopes`
AT_BOUND = 1e-6  # unit box: a variable this close to 0 or 1 sits on its bound at the start
ITERATIONS = 30  # Newton steps per active set
ROUNDS = 6  # active sets tried
HELD = 6  # rounds more, for the variables a step stopped at their bound (`_newton`'s ratio test)
STEP_TOL = 1e-10  # unit box: a Newton step this small has converged (round-off of the
# slopes leaves steps of 1e-12 on a well-posed problem; six printed digits need 1e-7)
PRINTED = 1e-7  # unit box: a Newton step this small whose model gains only round-off of f is the
# root to the printed digits, where an ill-conditioned Hessian leaves the slopes' round-off a jitter
# above STEP_TOL (`_newton`'s rescue)
NEAR = 1e-4  # unit box: a step this small is taken whole (no line search: the merit no
# longer resolves it, while Newton converges quadratically from here)
AGAIN = 3  # settles from the last one's end, while they lower f: the binding set read at a
# KKT point of one set can be another (a bound and a constraint that nearly coincide)
HALVINGS = 12  # step halvings before Newton gives up on an active set
SR1_SKIP = 1e-8  # `_secant`: an update whose r^T s is below this share of |r| |s| is skipped
RIDGE = 1e-12  # relative ridge on H (a flat direction, a continuum of optima)
SIGN_TOL = 1e-10  # a multiplier below -SIGN_TOL * (|g| + 1) has the wrong sign
ROUND_OFF = 1e-13  # relative change of the merit that is round-off
FEASIBLE = 1e-10  # an inactive constraint may fall this far below 0
BATCH_ROWS = 2048  # `_lagrangian_hessian`: points in one call of `evaluate_many`, counted as the
# 4n + 1 rows of their `slopes_many` each, and the Points alive at once (motion with 200 poses: 2 a
# call, peak 130 MiB against 105 one point at a time; with 11 poses all 22 in one call)
STALLED = 0.5  # curvature="stalled": steps shrinking by less than this a step stall. The differenced
# Hessian costs 2 gradients a group, about as many Newton steps; Gauss-Newton at a rate of 1/2 needs
# about 20 steps from NEAR to STEP_TOL, so below it Gauss-Newton is the cheaper (arc6_timed's rates
# are 0.02 to 0.35: at 0.25 its settles took the differenced Hessian, 76,612 -> 215,029 evaluations)
STALL_RATE = {True: 0.25, "stalled": STALLED}  # each curvature's stall threshold (True: the
# constraints' curvature is added at every step already, the whole Hessian only below a quarter)
DEPENDENT = 1e-8  # an active gradient with less than this share of its norm outside the
# span of the others' adds no condition (finite-difference slopes are exact to ~1e-10)


@dataclass
class Point:
    """What `settle` needs at u: objective f, gradient g (n,), constraint values c (m,)
    (>= 0 feasible, order-one scale) and their Jacobian a (m, n); h (n, n) a model of the
    Hessian of f, or None to have `settle` form the Hessian of the Lagrangian by central
    differences of g - a^T lambda."""

    f: float
    g: np.ndarray
    c: np.ndarray
    a: np.ndarray
    h: np.ndarray | None = None


@dataclass(frozen=True)
class Options:
    """How `settle` runs (its keyword arguments, held together for its rounds)."""

    evaluate: Callable[[np.ndarray], Point]
    hessian_step: float
    active_tol: float
    multipliers: bool
    step_tol: float
    curvature: bool | str
    groups: list | None
    evaluate_many: Callable[[np.ndarray], list] | None = None
    reuse: bool = False
    memo: dict = field(default_factory=dict)  # reuse: the last differenced Hessian (`_hessian`)


@dataclass
class Settled:
    u: np.ndarray
    f: float
    worst: float  # largest constraint violation (max(0, -c)), box excluded
    converged: bool  # the KKT residual vanished with multipliers of the right sign


def settle(evaluate: Callable[[np.ndarray], Point], u0, hessian_step: float = 1e-6,
           active_tol: float = ACTIVE, multipliers: bool = False, step_tol: float = STEP_TOL,
           curvature: bool | str = False, groups=None, evaluate_many=None, reuse: bool = False) -> Settled:
    """Newton-KKT from u0 on the active set found there (constraints within `active_tol`
    of 0: above the margin a search keeps from its limits; see the module docstring).
    A round that ends with a multiplier of the wrong sign (or fails on it) releases the
    most negative one, a round that breaks an inactive constraint adds it, and the next
    round starts again from u0. `evaluate` may raise to stop (a spent budget): the
    exception passes through. `multipliers`: each round's first Hessian of the Lagrangian
    at least-squares multipliers (g = A^T lambda) instead of 0: a linear objective (an
    epigraph's, maximize t) has no curvature of its own, and with fewer binding constraints
    than free variables its first Newton system would be singular. `step_tol`: the Newton
    step (unit box) that counts as converged (slopes taken with a small step, against a
    sharp bend, leave a round-off jitter above STEP_TOL). `curvature`: the Points' h models
    f's Hessian alone (Gauss-Newton), and the active constraints' curvature
    -sum lambda_i Hess c_i is added by central differences of their gradients (steps
    `hessian_step`): without it a constraint that bends under a large multiplier leaves
    Newton-KKT linear at best, and its line search stalls short of the root. Where the
    steps shrink only linearly or grow, the whole Hessian of the Lagrangian by differences
    (a residual's own curvature that Gauss-Newton misses). `curvature="stalled"`: that
    differenced Hessian only where the steps stall (shrink by less than STALLED a step, or
    grow), Gauss-Newton alone elsewhere (each differenced Hessian costs 2 gradients a
    group: with constraints that are mostly linear, such as the Grashof inequalities,
    adding their curvature at every step spends a budget for nothing).
    A converged settle starts again from its end point (at most AGAIN times) while that
    lowers f: there the binding set is read afresh, and a set that held at the first end
    point (a variable within AT_BOUND of its bound left free, a constraint beside it held)
    can give way to a better one. `evaluate_many`: the Points of many u (K, n) at once (one
    batch of the caller's vectorized function, `slopes_many`), for the differenced
    Hessian's 2 points a group, which use their f, g, c and a only (h may be None there);
    None: `evaluate` point by point. `reuse`: a differenced Hessian of the Lagrangian, once
    formed, serves every later step within NEAR of where it was formed on the same binding
    set (the rounds and the settles from an end included): near the root a Hessian off by
    O(NEAR) costs a factor O(NEAR) a step in Newton's rate, while each new one costs 2
    gradients a group (the front's 10-point path: 5 Hessians a settle, 1 with reuse).
    `curvature="whole"`: that differenced Hessian at every step, from the first (with
    `reuse`, one per NEAR-neighbourhood and binding set): where a binding constraint's own
    curvature is all that holds a flat direction of f (an epsilon level of a Pareto front:
    Gauss-Newton's model is singular along the level, its steps cycle outside NEAR)."""
    if curvature not in (False, True, "stalled", "whole"):
        raise ValueError(f"curvature must be False, True, 'stalled' or 'whole', not {curvature!r}")
    opts = Options(evaluate, hessian_step, active_tol, multipliers, step_tol, curvature, groups, evaluate_many,
                   reuse)
    out = _settle_once(opts, u0)
    for _ in range(AGAIN):  # from its end, where the binding set is read afresh
        if not out.converged:
            break
        again = _settle_once(opts, out.u)
        if not (again.converged and again.f < out.f - ROUND_OFF * abs(out.f)
                and again.worst <= max(out.worst, FEASIBLE)):
            break
        out = again
    return out


def _settle_once(opts: Options, u0) -> Settled:
    """`settle` from u0 once: Newton-KKT rounds on the binding set read at u0, changed as
    the multipliers' signs and the broken constraints say."""
    evaluate = opts.evaluate
    start = np.clip(np.asarray(u0, dtype=float), 0.0, 1.0)
    p = evaluate(start)
    active = p.c <= opts.active_tol
    lower, upper = start <= AT_BOUND, start >= 1.0 - AT_BOUND
    here = start
    tried = set()  # (point, binding set) of each round begun: one begun again ends as it did (a
    # failed round releases a bound its next round meets again); the last round's end is returned
    u = start
    for _ in range(ROUNDS + HELD):
        begin = np.where(lower, 0.0, np.where(upper, 1.0, here))
        key = (begin.tobytes(), active.tobytes(), lower.tobytes(), upper.tobytes())
        if key in tried and not opts.reuse:
            break
        tried.add(key)
        u, p, lam, ok = _newton(opts, begin, evaluate(begin), active, lower | upper)
        broken = ~active & (p.c < -FEASIBLE)
        if isinstance(ok, tuple) and not broken.any():  # a step stopped where variable ok[1] met
            (upper if u[ok[1]] >= 0.5 else lower)[ok[1]] = True  # its bound: held there from here
            here = u
            continue
        here = u if ok else start  # a round that failed leaves no point to go on from
        # multipliers of the bounds: the gradient of the Lagrangian pushing outwards
        grad_l = p.g - linalg.matvec(p.a[active].T, lam) if active.any() else p.g
        scale = float(np.max(np.abs(p.g), initial=0.0)) + 1.0
        wrong = np.full(len(p.c) + 2 * len(u), 0.0)  # how wrong: constraints, lower, upper
        wrong[np.flatnonzero(active)] = -lam
        wrong[len(p.c):len(p.c) + len(u)] = np.where(lower, -grad_l, 0.0)
        wrong[len(p.c) + len(u):] = np.where(upper, grad_l, 0.0)
        worst_sign = int(np.argmax(wrong))
        if wrong[worst_sign] > SIGN_TOL * scale:  # release the most wrong one
            if worst_sign < len(p.c):
                active[worst_sign] = False
            elif worst_sign < len(p.c) + len(u):
                lower[worst_sign - len(p.c)] = False
            else:
                upper[worst_sign - len(p.c) - len(u)] = False
            continue
        broken = ~active & (p.c < -FEASIBLE)
        if not broken.any():
            if not ok:
                break
            worst = float(np.max(np.maximum(0.0, -p.c), initial=0.0)) + 0.0
            return Settled(u, float(p.f), worst, True)
        active |= broken  # also after a failed round: its path crossed them (they bind)
    worst = float(np.max(np.maximum(0.0, -p.c), initial=0.0)) + 0.0
    return Settled(u, float(p.f), worst, False)


def _newton(opts: Options, u, p: Point, active, fixed):
    """Newton steps on the KKT system with `active` constraints as equalities and the
    `fixed` variables held; a step is halved until the merit f + rho |c_A|_1 falls (rho
    above every multiplier). Returns (u, point, multipliers, ok); ok is ("bound", k) where
    a step stopped at variable k's bound (`_to_bound`), for `_settle_once` to hold it."""
    evaluate, curvature, hessian_step, groups = opts.evaluate, opts.curvature, opts.hessian_step, opts.groups
    many = opts.evaluate_many or (lambda us: [evaluate(v) for v in us])
    free = np.flatnonzero(~fixed)
    rows = np.flatnonzero(active)
    lam = np.zeros(len(rows))
    if len(free) == 0:
        return u, p, lam, True
    if opts.multipliers and len(rows):  # least squares g = A^T lambda over the free variables
        af = p.a[rows][:, free]
        lam = linalg.solve(linalg.gram(af.T), linalg.matvec(af, p.g[free]))
        lam = np.where(np.isfinite(lam), lam, 0.0)
    full, last = False, np.inf  # curvature: the differenced Hessian in use; the last step's size
    stale = False  # reuse: the last step, on a kept Hessian, shrank by less than the stall rate
    kept = False  # the last step's Hessian was a kept one
    rest = None  # (u, p, lambda) of the first iterate where the model had only round-off left to gain
    gauss_newton = p.h is not None and curvature is False  # the model: the Points' h alone
    secant = None  # Gauss-Newton's correction along the steps taken (`_secant`), once they stall
    before = None  # the last iterate (u, Point)

    def failed():  # the pass fails, unless an iterate was at round-off (`_at_round_off`): that one
        return (*rest, True) if rest else (u, p, lam, False)

    for _ in range(ITERATIONS):
        if p.h is None or (curvature and full) or curvature == "whole":
            h, kept = _hessian(opts, many, u, rows, free, lam, fresh=stale)
        elif curvature is True and len(rows) and np.any(lam != 0.0):
            h = p.h + _lagrangian_hessian(many, u, rows, lam, hessian_step, objective=False, groups=groups)
        else:
            h = p.h
        if secant is not None:  # corrected by the last step's change of the gradient
            secant = _secant(secant, h, u - before[0], _grad_l(p, rows, lam) - _grad_l(before[1], rows, lam), free)
        step, lam_new = _kkt_step(h if secant is None else h + secant, p.g, p.a[rows], p.c[rows], free)
        if step is None:
            return failed()
        size = float(np.max(np.abs(step)))
        if gauss_newton and secant is None and before is not None and size > STALLED * last:
            # steps that do not shrink: Gauss-Newton misses a residual's curvature along them
            secant = _secant(np.zeros_like(h), h, u - before[0],
                             _grad_l(p, rows, lam) - _grad_l(before[1], rows, lam), free)
            step, lam_new = _kkt_step(h + secant, p.g, p.a[rows], p.c[rows], free)
            if step is None:
                return failed()
            size = float(np.max(np.abs(step)))
        before = (u, p)
        lam_old, lam = lam, lam_new
        if rest is None and size <= PRINTED and _at_round_off(p, h, step, rows, lam):
            rest = (u, p, lam)
        stale = kept and not size <= STALL_RATE.get(curvature, STALLED) * last
        kept = False
        if curvature and size <= NEAR:  # Newton's region: steps that shrink only linearly say
            # the model misses curvature (a large residual's): the differenced Hessian then;
            # steps that grow under it say it is worse (round-off in a flat valley): back
            full = size < last if full else size > STALL_RATE.get(curvature, STALLED) * last
        last = size
        if size <= NEAR:  # Newton's own region: the step is taken whole
            u = np.clip(u + step, 0.0, 1.0)
            p = evaluate(u)
            if size <= opts.step_tol:  # the root to round-off
                break
            continue
        rho = 2.0 * float(np.max(np.abs(lam), initial=0.0)) + 1e-300
        merit = p.f + rho * float(np.sum(np.abs(p.c[rows])))
        residual = _kkt_residual(p, rows, lam, free)
        share, hit = _to_bound(u, step, free)
        t = share
        for _ in range(HALVINGS):
            trial = np.clip(u + t * step, 0.0, 1.0)
            if t == share and hit >= 0:
                trial[hit] = 1.0 if step[hit] > 0 else 0.0
            q = evaluate(trial)
            # progress: a lower merit, or (where the merit no longer resolves the step: a
            # change within round-off) a smaller KKT residual
            m_q = q.f + rho * float(np.sum(np.abs(q.c[rows])))
            if m_q < merit or (m_q <= merit + ROUND_OFF * abs(merit)
                               and _kkt_residual(q, rows, lam, free) < residual):
                break
            t *= 0.5
        else:
            if size < 1e-9:  # round-off size: the root to working precision
                return u, p, lam, True
            if secant is not None:  # the corrected model's step is no descent (module docstring):
                secant, before, last, lam = None, None, np.inf, lam_old  # Gauss-Newton's from here
                continue
            return failed()
        if t == share and hit >= 0:  # at the bound: the next round holds it (`_settle_once`)
            return trial, q, lam, ("bound", hit)
        u, p = trial, q
    else:  # still moving after ITERATIONS steps: not settled
        return failed()
    return u, p, lam, True


def _grad_l(p: Point, rows, lam):
    """The gradient of the Lagrangian, g - A_rows^T lambda."""
    return p.g - linalg.matvec(p.a[rows].T, lam) if len(rows) else p.g


def _secant(correction, h, s, y, free):
    """The symmetric rank-one update of `correction` so that the model h + correction meets
    the secant condition (h + correction) s = y over the free variables (Nocedal & Wright,
    Numerical Optimization, 2nd ed., 2006, eq. 6.24; skipped, as there, where r^T s is below
    SR1_SKIP |r| |s|). Added to Gauss-Newton's 2 J^T J it supplies the curvature of large
    residuals that the model misses, along the directions Newton has moved (the structured
    secant idea of Dennis, Gay & Welsch, ACM TOMS 7 (1981), NL2SOL): a free-timing path on
    the crank-rocker's edge, one target near the fold of its coupler curve, leaves the model
    half the curvature of its flat valley, and Newton's steps there swing back and forth."""
    r = np.zeros(len(s))
    r[free] = (y - linalg.matvec(h + correction, s))[free]
    rs = linalg.dot(r, s)
    if abs(rs) <= SR1_SKIP * float(np.sqrt(linalg.dot(r, r) * linalg.dot(s, s))) or not np.isfinite(rs):
        return correction
    return correction + np.outer(r, r) / rs


def _to_bound(u, step, free) -> tuple[float, int]:
    """The ratio test on the box (Nocedal & Wright, sec. 16.6): the share of `step` at which
    the first free variable strictly inside the box meets its bound, and that variable; (1.0,
    -1) when the whole step stays inside. A Newton step along a flat valley can run far past
    a bound; clipped there it is no longer Newton's, and its line search stalls on an optimum
    that lies on the bound (a path's output at its largest length, closed18_free). Stopped at
    the bound instead, the variable is held there by the next round and released by its
    multiplier's sign if it should not be."""
    inside = np.zeros(len(u), dtype=bool)
    inside[free] = True
    inside &= (u > AT_BOUND) & (u < 1.0 - AT_BOUND)
    with np.errstate(divide="ignore", invalid="ignore"):
        room = np.where(step > 0.0, (1.0 - u) / step, np.where(step < 0.0, -u / step, np.inf))
    room = np.where(inside, room, np.inf)
    k = int(np.argmin(room))  # the first of equal ones
    return (float(room[k]), k) if room[k] < 1.0 else (1.0, -1)


def _hessian(opts: Options, many, u, rows, free, lam, fresh: bool):
    """The differenced Hessian of the Lagrangian at u (`_lagrangian_hessian`), or, with
    `opts.reuse`, the last one formed within NEAR of u on the same binding set, unless
    `fresh` (the steps under it stall); (Hessian, whether a kept one)."""
    key = (tuple(rows.tolist()), tuple(free.tolist()))
    last = opts.memo.get("hessian")
    if (opts.reuse and not fresh and last is not None and last[0] == key
            and float(np.max(np.abs(u - last[1]))) <= NEAR):
        return last[2], True
    h = _lagrangian_hessian(many, u, rows, lam, opts.hessian_step, groups=opts.groups)
    if opts.reuse:
        opts.memo["hessian"] = (key, np.array(u, dtype=float), h)
    return h, False


def _at_round_off(p: Point, h, step, rows, lam) -> bool:
    """Whether Newton's model at p gains only round-off of f along `step` (its slope
    |grad L . s| and curvature |s^T H s| / 2, below ROUND_OFF |f|) with the active
    constraints met (within FEASIBLE). `_newton` ends there, the root to the printed digits,
    when its steps do not shrink below the step tolerance: the slopes' round-off, divided by
    a Hessian's smallest eigenvalue (a flat valley), moves the root by more (motion study case
    39, one length at its bound: steps of 1.5e-8 to 3e-8 that grew, f constant to 1e-15)."""
    if len(rows) and float(np.max(np.abs(p.c[rows]))) > FEASIBLE:
        return False
    grad_l = p.g - linalg.matvec(p.a[rows].T, lam) if len(rows) else p.g
    gain = abs(linalg.dot(grad_l, step)) + 0.5 * abs(linalg.dot(step, linalg.matvec(h, step)))
    return gain <= ROUND_OFF * abs(p.f)


def slopes(values: Callable[[np.ndarray], np.ndarray], u: np.ndarray, step: float = SLOPE_STEP):
    """(values at u (m,), Jacobian (m, n)) of a vectorized function of unit-box points
    ((N, n) -> (N, m)) by fourth-order differences, every column at u itself: the central
    (8 (v(u + h) - v(u - h)) - (v(u + 2h) - v(u - 2h))) / (12 h), or, for a variable within
    2h of a bound, the one-sided (-25 v(u) + 48 v(u + h) - 36 v(u + 2h) + 16 v(u + 3h)
    - 3 v(u + 4h)) / (12 h) with h pointing into the box (Fornberg, Math. Comp. 51 (1988),
    the weights of the 5-point stencils). Moving the whole point inside instead would
    take every column at another point, an O(h) error in the gradient that Newton cannot
    settle below. The step is large (round-off in the slopes ~ eps / h is what leaves a
    Newton root uncertain) since the truncation error ~ h^4 is small and the same on every
    machine. One batch of 4n + 1 points."""
    v0, jac = slopes_many(values, np.asarray(u, float)[None, :], step)
    return v0[0], jac[0]


def slopes_many(values: Callable[[np.ndarray], np.ndarray], u: np.ndarray, step: float = SLOPE_STEP):
    """`slopes` at each of K points u (K, n): (values (K, m), Jacobians (K, m, n)), from
    one batch of K (4n + 1) points."""
    k, n = u.shape
    one_sided = np.where(u < 2.0 * step, 1.0, np.where(u > 1.0 - 2.0 * step, -1.0, 0.0))  # (K, n)
    h = np.where(one_sided < 0.0, -step, step)  # into the box where one-sided
    # each column's four offsets, in steps h: central (1, -1, 2, -2), one-sided (1, 2, 3, 4)
    offsets = np.where(one_sided[:, None, :] != 0.0, np.array([1.0, 2.0, 3.0, 4.0])[:, None],
                       np.array([1.0, -1.0, 2.0, -2.0])[:, None])  # (K, 4, n)
    shifts = (offsets * h[:, None, :])[:, :, :, None] * np.eye(n)  # (K, 4, n, n)
    points = np.concatenate([u[:, None, :], (u[:, None, None, :] + shifts).reshape(k, 4 * n, n)], axis=1)
    batch = values(points.reshape(k * (4 * n + 1), n)).reshape(k, 4 * n + 1, -1)
    v0, v = batch[:, 0], batch[:, 1:].reshape(k, 4, n, -1)
    central = 8.0 * (v[:, 0] - v[:, 1]) - (v[:, 2] - v[:, 3])
    forward = -25.0 * v0[:, None, :] + 48.0 * v[:, 0] - 36.0 * v[:, 1] + 16.0 * v[:, 2] - 3.0 * v[:, 3]
    jac = np.where((one_sided != 0.0)[:, :, None], forward, central) / (12.0 * h[:, :, None])
    return v0, np.transpose(jac, (0, 2, 1))


def least_squares_points(v, jac, m: int, gauss_newton: bool, jr=None) -> list[Point]:
    """The Points of f = |r|^2 at K points from their values v (K, m + c) -- the residuals r
    first, then the constraints c -- and Jacobians jac (K, m + c, n) (`slopes_many`):
    g = 2 J^T r, and h = 2 J^T J where `gauss_newton` (None elsewhere: the differenced
    Hessian's points read f, g, c and a alone). jr (K, m, n): the residuals' Jacobians to
    use instead of jac's first m rows (closed-form slopes)."""
    r = v[:, :m]
    jr = jac[:, :m] if jr is None else jr
    f, g = linalg.dot(r, r), 2.0 * linalg.matvec(np.swapaxes(jr, 1, 2), r)
    h = 2.0 * linalg.gram(jr) if gauss_newton else [None] * len(v)
    return [Point(float(f[i]), g[i], v[i, m:], jac[i, m:], h=h[i]) for i in range(len(v))]


def _kkt_residual(p: Point, rows, lam, free) -> float:
    """|grad f - A^T lambda| over the free variables plus |c_A| (max norms)."""
    grad_l = p.g - linalg.matvec(p.a[rows].T, lam) if len(rows) else p.g
    return float(np.max(np.abs(grad_l[free]), initial=0.0)) + float(np.max(np.abs(p.c[rows]), initial=0.0))


def _kkt_step(h, g, a, c, free):
    """The Newton-KKT step over the free variables (zero on the others) and the new
    multipliers, or (None, None) if the system is singular. Active constraints whose
    gradients over the free variables depend on the others' (two Grashof inequalities
    that coincide once the lengths at their bounds are held) are left out of the system
    with multiplier 0: the kept ones' linearization holds them too."""
    k = len(free)
    af = a[:, free]
    rows = independent_rows(af)
    m = len(rows)
    hf = h[np.ix_(free, free)]
    ridge = RIDGE * max(float(np.max(np.abs(np.diag(hf)), initial=0.0)), 1e-300)
    kkt = np.zeros((k + m, k + m))
    kkt[:k, :k] = hf + ridge * np.eye(k)
    kkt[:k, k:] = -af[rows].T
    kkt[k:, :k] = af[rows]
    rhs = np.concatenate([-g[free], -c[rows]])
    sol = linalg.solve(kkt, rhs)
    if not np.all(np.isfinite(sol)):
        return None, None
    step = np.zeros(len(g))
    step[free] = sol[:k]
    lam = np.zeros(len(c))
    lam[rows] = sol[k:]
    return step, lam


def independent_rows(a: np.ndarray, tol: float = DEPENDENT) -> list[int]:
    """Indices of the rows of a (m, n), in order, each of which keeps more than `tol` of
    its norm after projection on the rows kept before it (Gram-Schmidt, done twice)."""
    kept, basis = [], []
    for i, row in enumerate(a):
        norm = float(np.sqrt(linalg.dot(row, row)))
        v = row.copy()
        for _ in range(2):
            for q in basis:
                v = v - linalg.dot(v, q) * q
        rest = float(np.sqrt(linalg.dot(v, v)))
        if rest > tol * norm:
            kept.append(i)
            basis.append(v / rest)
    return kept


def _lagrangian_hessian(points, u, rows, lam, h_step, objective: bool = True, groups=None):
    """Central differences of grad f - A^T lambda (`objective` False: of -A^T lambda alone,
    the active constraints' curvature), symmetrized; steps kept inside the box. `groups`
    (index arrays covering the variables, or None: each variable alone) are differenced
    together, one pair of points a group (Curtis, Powell & Reid, J. Inst. Maths Applics 13
    (1974), column grouping): the members of a group of more than one must share no Hessian
    entry with one another nor with another such group's members (free timing's input
    angles: each moves its own pose's residuals alone), so that each member's own slope
    gives its diagonal entry; its entries with the variables differenced alone come from
    their columns (symmetry). The cost is two gradients a group, not a variable, evaluated
    together: `points` maps the 2 x groups points (K, n) to their Points, as many groups a
    call as BATCH_ROWS allows (memory bounded whatever n)."""
    n = len(u)
    groups = [np.array([j]) for j in range(n)] if groups is None else [np.asarray(g, int) for g in groups]
    h = np.zeros((n, n))

    def slope(p):
        g = p.g if objective else np.zeros(n)
        return g - linalg.matvec(p.a[rows].T, lam) if len(rows) else g

    per_call = max(1, BATCH_ROWS // (2 * (4 * n + 1)))  # groups whose point pairs go in one call
    for first in range(0, len(groups), per_call):
        chunk = groups[first:first + per_call]
        steps = np.zeros((len(chunk), n))
        for i, g in enumerate(chunk):
            steps[i, g] = h_step
        his, los = np.clip(u + steps, 0.0, 1.0), np.clip(u - steps, 0.0, 1.0)
        at = points(np.stack([his, los], axis=1).reshape(2 * len(chunk), n))  # hi, lo of each group
        for i, g in enumerate(chunk):
            d = slope(at[2 * i]) - slope(at[2 * i + 1])
            width = np.maximum(his[i, g] - los[i, g], 1e-300)
            if len(g) == 1:
                h[:, g[0]] = d / width[0]
            else:
                h[g, g] = d[g] / width  # each member's own slope: its diagonal entry alone
    many = [g for g in groups if len(g) > 1]
    if many:
        together = np.concatenate(many)
        h[:, together] = h[together, :].T  # their other entries: the single columns' (symmetry)
    return 0.5 * (h + h.T)
