"""Multi-start least squares for precision positions (numpy only, vectorized over starts).

Starts are Freudenstein solutions (Freudenstein 1955, Trans. ASME 77):

    K1 cos(psi) - K2 cos(phi) + K3 = cos(phi - psi),   a = d/K1, c = d/K2,
    b^2 = a^2 + c^2 + d^2 - 2 a c K3,

the linear least-squares one over every position and the exact ones through subsets of
three positions, each on both branches. A negative a (or c) means the link points the
other way: the start keeps that orientation (its physical angle is phi + pi, or psi + pi)
and refines positive lengths. Every start is refined at once by damped Newton steps (Levenberg-Marquardt with a finite-difference Hessian) on
the true output-angle error of the assembled linkage (the conventions of docs/format.md closure), over
parameters that assemble at every position by construction (`lengths`): a start that does
not assemble is first moved to the nearest lengths that do, so the search is never stopped
by a non-assembling position nor pulled into one.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations

import numpy as np

from linkcli.mechanisms.four_bar.kinematics import TWO_PI, choose_arc, ground_distance, input_arcs, wrap

MAX_SUBSETS = 35  # three-position subsets tried: all of them up to C(7, 3) = 35
SPREAD = 7  # for more positions: every triple of 7 evenly spread positions (ends included)
SINGULAR = 1e12  # condition number above which a 3x3 Freudenstein system is not solved
STAGE = 15  # iterations every start gets before the most promising are kept
KEEP = 3  # starts kept after the first stage, by cost and by cost among those that travel
MAX_ITER = 200  # further iterations of the kept starts
STALL = 10  # iterations over which a start that cannot catch up is recognised
ROUNDING = 16 * np.finfo(float).eps  # relative margin of |b - c| against round-off
LO = np.array([-14.0, -32.0, -1e7])  # a within e^+-14 of d (~1e6), q^4 <= 1e6 (b + c <= R + 1e6 d)
HI = -LO
FD_STEP = 1e-5  # finite-difference step on (s, q, t) for the gradient and Hessian
FTOL = 1e-14  # relative gain of an accepted, nearly Newton step: converged below it
GTOL = 1e-10  # gradient J^T r (inf-norm, over 1 + rms error) under which a start has converged


def subsets(n: int) -> np.ndarray:
    """Index triples (T, 3): all C(n, 3) if at most MAX_SUBSETS, else every triple of
    SPREAD evenly spread positions (first and last included). Deterministic."""
    if n < 3:
        return np.empty((0, 3), dtype=int)
    picks = range(n) if n * (n - 1) * (n - 2) // 6 <= MAX_SUBSETS else \
        np.unique(np.round(np.linspace(0, n - 1, SPREAD)).astype(int))
    return np.array(list(combinations(picks, 3)), dtype=int)


def freudenstein_system(phi, psi):
    """Rows [cos psi, -cos phi, 1] and right-hand side cos(phi - psi), any leading shape."""
    m = np.stack([np.cos(psi), -np.cos(phi), np.ones_like(phi)], axis=-1)
    return m, np.cos(phi - psi)


def ratio_starts(phi, psi) -> np.ndarray:
    """K (S, 3): the least-squares ratios over all positions, then the exact ratios of each
    non-singular three-position subset."""
    m, rhs = freudenstein_system(phi, psi)
    ks = [np.linalg.lstsq(m, rhs, rcond=None)[0][None, :]]
    idx = subsets(len(phi))
    if len(idx):
        ms, rs = m[idx], rhs[idx]  # (T, 3, 3), (T, 3)
        ok = np.linalg.cond(ms) < SINGULAR
        if np.any(ok):
            ks.append(np.linalg.solve(ms[ok], rs[ok][..., None])[..., 0])
    return np.concatenate(ks)


def lengths_of(k: np.ndarray, d: float):
    """Signed (a, c) and b^2 (S,) of ratio rows k; rows with K1 or K2 ~ 0 give inf."""
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.where(np.abs(k[:, 0]) > 1e-12, d / k[:, 0], np.inf)
        c = np.where(np.abs(k[:, 1]) > 1e-12, d / k[:, 1], np.inf)
        b2 = a * a + c * c + d * d - 2 * a * c * k[:, 2]
    return a, b2, c


@dataclass
class Starts:
    """Start points: log-lengths x (S, 3), orientation signs of a and c, branch signs."""

    x: np.ndarray
    sa: np.ndarray
    sc: np.ndarray
    sign: np.ndarray


def make_starts(phi, psi, d: float) -> Starts:
    """Usable Freudenstein starts (finite links, real coupler), duplicates removed, each on
    both branches (open first). Order: least squares first, then the subsets."""
    a, b2, c = lengths_of(ratio_starts(phi, psi), d)
    ok = np.isfinite(a) & np.isfinite(c) & np.isfinite(b2) & (b2 > 0) & (a != 0) & (c != 0)
    a, b2, c = a[ok], b2[ok], c[ok]
    x = np.log(np.column_stack([np.abs(a), np.sqrt(b2), np.abs(c)]))
    key = np.column_stack([np.round(x, 6), np.sign(a), np.sign(c)])
    _, first = np.unique(key, axis=0, return_index=True)
    keep = np.sort(first)
    x, sa, sc = x[keep], np.sign(a[keep]), np.sign(c[keep])
    s = len(x)
    return Starts(x=np.repeat(x, 2, axis=0), sa=np.repeat(sa, 2), sc=np.repeat(sc, 2),
                  sign=np.tile([-1.0, 1.0], s))


def physical_angles(phi, psi, sa, sc):
    """(S, n) physical input and output angles of each start: +pi where a link is turned."""
    return (phi[None, :] + np.where(sa < 0, np.pi, 0.0)[:, None],
            psi[None, :] + np.where(sc < 0, np.pi, 0.0)[:, None])


def closure_gap(a, b, c, rho):
    """How far the loop misses closing (length unit): rho beyond [|b - c|, b + c], else 0."""
    return np.maximum(np.maximum(rho - (b + c), np.abs(b - c) - rho), 0.0)


def lengths(x, phi_p, d, gaps=False):
    """Lengths (a, b, c), each (k, 1), of parameters x = (s, q, t) (k, 3) that always
    assemble at the input angles phi_p (k, n).

    The loop closes at phi_i iff |b - c| <= rho_i <= b + c, rho_i = |A_i B0|. With
    R_hi = max rho_i(a), R_lo = min rho_i(a), the map
        a = d e^s,  b + c = u = R_hi + d q^4,  b - c = v = R_lo sin((pi/2) sin t)
    covers exactly the lengths that assemble at every position, boundary included
    (q = 0: a toggle with b + c = rho; sin t = +-1: a toggle with |b - c| = rho). So an
    unconstrained least-squares search on (s, q, t) searches assembling linkages only.
    The fourth powers make the closure smooth at the boundary: alpha grows like the
    square root of the margin (u - rho, ...), here like q^2, so a fit held at a toggle is a
    smooth stationary point, not a kink. With gaps=True also returns rho, u and the three
    margins u - rho, rho - v, rho + v (k, n), all >= 0, formed without cancellation:
    (R_hi - rho) + d q^4, (rho - R_lo) + R_lo (1 -+ sin m), m = (pi/2) sin t, with
    1 - sin m = 2 sin^2((pi/2) sin^2(pi/4 - t/2)), 1 + sin m = 2 sin^2((pi/2) cos^2(pi/4 - t/2))."""
    a = d * np.exp(x[:, 0:1])
    rho = ground_distance(a, d, phi_p)
    r_hi, r_min = rho.max(axis=1, keepdims=True), rho.min(axis=1, keepdims=True)
    q2, t = x[:, 1:2] ** 2, x[:, 2:3]
    u = r_hi + d * q2 * q2
    # |b - c| held ROUNDING * u inside R_lo: b and c are stored to an ulp of u, and a
    # long coupler and output (u >> rho) would otherwise miss closing by round-off
    r_lo = np.maximum(r_min - ROUNDING * u, 0.0)
    v = r_lo * np.sin(np.pi / 2 * np.sin(t))
    abc = (a, (u + v) / 2, (u - v) / 2)
    if not gaps:
        return abc
    half = np.pi / 4 - t / 2
    outer = (r_hi - rho) + d * q2 * q2
    inside = (rho - r_min) + (r_min - r_lo)
    inner_lo = inside + 2 * r_lo * np.sin(np.pi / 2 * np.sin(half) ** 2) ** 2
    inner_hi = inside + 2 * r_lo * np.sin(np.pi / 2 * np.cos(half) ** 2) ** 2
    return abc, rho, u, outer, inner_lo, inner_hi


def closure(x, phi_p, sign, d):
    """Output angles psi (k, n) of the linkages of x on their branches: the conventions of docs/format.md,
    psi = theta_rho -+ alpha, with alpha from its half angle

        tan(alpha / 2) = sqrt((u - rho)(rho + v) / ((rho - v)(u + rho))),

    (cos alpha = (rho^2 + c^2 - b^2) / (2 rho c), u = b + c, v = b - c), the margins
    computed without cancellation so that alpha keeps full precision at a toggle (where
    the arccos form loses half the digits and would make a finite-difference Jacobian
    noisy)."""
    (a, _, _), rho, u, outer, inner_lo, inner_hi = lengths(x, phi_p, d, gaps=True)
    theta_rho = np.arctan2(a * np.sin(phi_p), a * np.cos(phi_p) - d)
    num = np.sqrt(np.maximum(outer * inner_hi, 0.0))
    den = np.sqrt(np.maximum(inner_lo * (u + rho), 0.0))
    alpha = 2.0 * np.arctan2(num, den)
    return theta_rho + sign[:, None] * alpha, rho > 0


def parameters(log_abc, phi_p, d):
    """(s, q, t) of log-lengths, the lengths first moved to the nearest assembling ones:
    b + c raised to R_hi, |b - c| lowered to R_lo (the start keeps its input link)."""
    a, b, c = (np.exp(log_abc[:, i:i + 1]) for i in range(3))
    rho = ground_distance(a, d, phi_p)
    r_hi, r_lo = rho.max(axis=1, keepdims=True), rho.min(axis=1, keepdims=True)
    q = np.sqrt(np.sqrt(np.maximum(b + c - r_hi, 0.0) / d))
    ratio = np.where(r_lo > 0, (b - c) / np.where(r_lo > 0, r_lo, 1.0), 0.0)
    t = np.arcsin(2 / np.pi * np.arcsin(np.clip(ratio, -1.0, 1.0)))
    return np.column_stack([np.log(a[:, 0] / d), q[:, 0], t[:, 0]])


def residuals(x, phi_p, psi_p, sign, d):
    """Output-angle errors wrap(psi - psi_target) (k, n) of the linkages of x on their
    branches, and where they assemble (everywhere but at rho = 0)."""
    psi, valid = closure(x, phi_p, sign, d)
    return wrap(psi - psi_p), valid


STENCIL = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [-1, 0, 0], [0, -1, 0], [0, 0, -1],
                    [1, 1, 0], [1, 0, 1], [0, 1, 1]], dtype=float)  # FD offsets, in steps


def derivatives(x, r, phi_p, psi_p, sign, d):
    """Gradient g = J^T r and Hessian H = J^T J + sum_i r_i grad^2 r_i of sum r^2 / 2
    (k, 3), (k, 3, 3), by finite differences with step FD_STEP: central for J and the pure
    second derivatives, forward for the mixed ones (9 residual evaluations per start, made
    in one vectorized call). Differences go through wrap, so a target near +-180 deg gives
    no 2 pi jump."""
    h, k, m = FD_STEP, len(x), len(STENCIL)
    pts = (x[:, None, :] + h * STENCIL[None, :, :]).reshape(k * m, 3)
    rep = np.repeat
    rr = residuals(pts, rep(phi_p, m, axis=0), rep(psi_p, m, axis=0), rep(sign, m), d)[0]
    dr = wrap(rr.reshape(k, m, -1) - r[:, None, :])  # (k, 9, n): r(x + h e) - r(x)
    plus, minus = dr[:, 0:3], dr[:, 3:6]
    jac = np.swapaxes(plus - minus, 1, 2) / (2 * h)  # (k, n, 3)
    second = np.empty((k, r.shape[1], 3, 3))
    for a in range(3):  # loops over the three variables, not over starts or points
        second[:, :, a, a] = (plus[:, a] + minus[:, a]) / (h * h)
    for col, (a, b) in enumerate(((0, 1), (0, 2), (1, 2))):
        second[:, :, a, b] = second[:, :, b, a] = (dr[:, 6 + col] - plus[:, a] - plus[:, b]) / (h * h)
    g = np.einsum("kni,kn->ki", jac, r)
    hess = np.einsum("kni,knj->kij", jac, jac) + np.einsum("kn,knij->kij", r, second)
    return g, hess


@dataclass
class Run:
    """Levenberg-Marquardt state of k starts: parameters, residual rows, assembly mask,
    cost sum r^2, damping, and whether each start has stopped by a convergence test."""

    x: np.ndarray
    r: np.ndarray
    valid: np.ndarray
    cost: np.ndarray
    lam: np.ndarray
    converged: np.ndarray


def levenberg_marquardt(x, phi_p, psi_p, sign, d, max_iter, budget=None, beaten=np.inf):
    """Damped Newton (Levenberg-Marquardt with the full Hessian) on every start at once,
    d fixed, over the assembling parameters (s, q, t) of `lengths`. Returns (Run, residual
    evaluations made: one per start per evaluation).

    The full Hessian (not only J^T J) matters: a fit held at a toggle is a stationary
    point where J^T J is singular in q or t and only the second-order term has curvature.
    Step: (H + mu I) dx = -g, mu = 1.5 max(0, -min eig H) + lam max|eig H|, accepted if it
    lowers sum r^2 (then lam / 10), else lam * 10 with H kept (Marquardt 1963; Nocedal &
    Wright, Numerical Optimization, 2nd ed., sec. 4.3). A start stops when the gradient
    is below GTOL (H positive semi-definite), an accepted near-Newton step gains less than
    FTOL of the cost, or lam exceeds 1e12 (no descent left); all stop after max_iter
    iterations or before an iteration would pass `budget` evaluations. A start whose cost
    is above `beaten` (a cost already reached) and fell by less than 1% of that excess over
    the last STALL iterations is abandoned (not converged): it cannot catch up.
    """
    x = np.clip(x, LO, HI)
    s = len(x)
    r, valid = residuals(x, phi_p, psi_p, sign, d)
    evaluations = s
    run = Run(x=x, r=r, valid=valid, cost=np.einsum("km,km->k", r, r), lam=np.full(s, 1e-3),
              converged=np.zeros(s, dtype=bool))
    grad, hess = np.zeros((s, 3)), np.zeros((s, 3, 3))
    stale = np.ones(s, dtype=bool)  # derivatives to recompute (x moved)
    history = [run.cost.copy()]
    stopped = np.zeros(s, dtype=bool)
    for _ in range(max_iter):
        if len(history) > STALL:
            before = history[-STALL - 1]
            stopped |= (run.cost > beaten * (1 + 1e-9)) & (before - run.cost < 0.01 * (run.cost - beaten))
        idx = np.nonzero(~run.converged & ~stopped)[0]
        if not len(idx):
            break
        need = idx[stale[idx]]
        if budget is not None and evaluations + len(STENCIL) * len(need) + len(idx) > budget:
            break
        if len(need):
            grad[need], hess[need] = derivatives(run.x[need], run.r[need], phi_p[need], psi_p[need],
                                                 sign[need], d)
            evaluations += len(STENCIL) * len(need)
            stale[need] = False
        g, h = grad[idx], np.where(np.isfinite(hess[idx]), hess[idx], 0.0)
        eig = np.linalg.eigvalsh(h)
        lam, cost = run.lam[idx], run.cost[idx]
        mu = 1.5 * np.maximum(-eig[:, 0], 0.0) + lam * (np.abs(eig).max(axis=1) + 1e-300)
        step = np.linalg.solve(h + mu[:, None, None] * np.eye(3), -g[..., None])[..., 0]
        x_new = np.clip(run.x[idx] + np.where(np.isfinite(step), step, 0.0), LO, HI)
        r_new, valid_new = residuals(x_new, phi_p[idx], psi_p[idx], sign[idx], d)
        evaluations += len(idx)
        cost_new = np.einsum("km,km->k", r_new, r_new)
        better = cost_new < cost
        flat = (np.abs(g).max(axis=1) <= GTOL * (1.0 + np.sqrt(cost))) & (eig[:, 0] >= -GTOL)
        done = flat | (better & (lam <= 1e-3) & (cost - cost_new <= FTOL * cost)) | (~better & (lam > 1e12))
        acc = idx[better]
        run.x[acc], run.r[acc], run.valid[acc] = x_new[better], r_new[better], valid_new[better]
        run.cost[acc] = cost_new[better]
        stale[acc] = True
        run.lam[idx] = np.where(better, np.maximum(lam / 10, 1e-12), lam * 10)
        run.converged[idx[done]] = True
        history.append(run.cost.copy())
    return run, evaluations


@dataclass
class Refined:
    """Refined starts: the starts run, lengths (k, 3), final residual rows, assembly mask,
    converged flags (False also for a start dropped after the first stage) and the
    residual evaluations made."""

    starts: Starts
    abc: np.ndarray
    r: np.ndarray
    valid: np.ndarray
    converged: np.ndarray
    evaluations: int


def refine(starts: Starts, phi, psi, d: float, budget: int | None = None) -> Refined:
    """Every start for STAGE iterations, then the most promising to convergence: the KEEP
    lowest costs, and the KEEP lowest among those that already travel from the first to
    the last position without a branch change (the order `solve` ranks by). A start that
    drifts towards infinite or vanishing links improves slowly and is dropped here."""
    if budget is not None:
        keep = max(1, min(len(starts.x), budget))
        starts = Starts(starts.x[:keep], starts.sa[:keep], starts.sc[:keep], starts.sign[:keep])
    phi_p, psi_p = physical_angles(phi, psi, starts.sa, starts.sc)
    run, evaluations = levenberg_marquardt(parameters(starts.x, phi_p, d), phi_p, psi_p, starts.sign,
                                           d, STAGE, budget)
    abc = np.concatenate(lengths(run.x, phi_p, d), axis=1)
    sweep = float(phi[-1] - phi[0])
    distinct = _distinct(np.argsort(run.cost, kind="stable"), abc, starts)
    moving = [i for i in distinct[:4 * KEEP] if run.valid[i].all() and travels(*abc[i], d, phi_p[i], sweep)]
    survivors = np.unique(np.array(distinct[:KEEP] + moving[:KEEP], dtype=int))
    done = [i for i in moving if run.converged[i]]
    beaten = run.cost[done[0]] if done else np.inf
    rest = None if budget is None else budget - evaluations
    if rest is None or rest > 0:
        sub, more = levenberg_marquardt(run.x[survivors], phi_p[survivors], psi_p[survivors],
                                        starts.sign[survivors], d, MAX_ITER, rest, beaten)
        evaluations += more
        run.x[survivors], run.r[survivors], run.valid[survivors] = sub.x, sub.r, sub.valid
        run.converged[survivors] = sub.converged | run.converged[survivors]
        abc[survivors] = np.concatenate(lengths(sub.x, phi_p[survivors], d), axis=1)
    return Refined(starts=starts, abc=abc, r=run.r, valid=run.valid, converged=run.converged,
                   evaluations=evaluations)


def _distinct(order, abc, starts) -> list:
    """Indices in `order`, leaving out a start whose lengths (relative 1e-6), orientation
    and branch repeat an earlier one: several starts often reach the same minimum."""
    seen, out = set(), []
    for i in order:  # a loop over a few dozen starts, once
        key = (starts.sa[i], starts.sc[i], starts.sign[i], *np.round(np.log(abc[i]) * 1e6).astype(np.int64))
        if key not in seen:
            seen.add(key)
            out.append(int(i))
    return out


def travels(a, b, c, d, phi_phys, sweep) -> bool:
    """Can the input move from the first to the last position (sweep = phi_n - phi_1, its
    sign the direction) inside one assembling arc, i.e. without passing a limit position
    where the linkage would change branch? A fully turning input always can."""
    arcs = input_arcs(a, b, c, d)
    if arcs is None:
        return True
    if not arcs:
        return False
    lo, hi = choose_arc(arcs, phi_phys[0])
    slack = 1e-9  # rad: a position at a limit up to round-off is inside the arc, on either side
    inside = np.mod(phi_phys - lo + slack, TWO_PI) <= (hi - lo) + 2 * slack
    first, last = np.mod(phi_phys[0] - lo + slack, TWO_PI), np.mod(phi_phys[-1] - lo + slack, TWO_PI)
    return bool(np.all(inside)) and ((sweep >= 0 and last >= first) or (sweep < 0 and last <= first))
