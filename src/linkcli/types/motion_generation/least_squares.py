"""Approximate motion generation: many poses (or bounds/constraints) by least squares.

Objective (docs/format.md, motion-generation): F = sum_i |P_i - T_i|^2 + (w * dangle_i)^2, P_i the
body origin reached at the input angle phi_i, T_i the target, dangle_i the wrapped angle
error in rad and w a length, by default the RMS distance of the target origins from their
centroid (poses.characteristic_length), so that a turn of 1 rad weighs like a typical
excursion of the body. Unknowns: the 10 linkage parameters (assemble.PARAM_NAMES) and,
with free timing, every phi_i; with prescribed timing phi_i = input_angles_i + offset.

Method: (1) a global stage evaluated on a whole population at once: a Latin hypercube
over the bounds, the linkages of the Burmester dyads of five-pose subsets and of 3-pose
inversions (moving pivots for sampled ground pivots), each scored with its best phi_i
from a grid (free timing; the inner minimization is exact up to the grid); (2) the best
distinct starts polished by scipy.optimize.least_squares (trust region reflective,
bounds, tolerances 1e-15) on the residual vector; (3) the best polished design that has no
branch or order defect and meets the constraints is returned, (4) after a final
Gauss-Newton settle to round-off (`_settle`, linkcli.search.kkt), so that its printed
digits do not follow least_squares' path.
"""

from __future__ import annotations

import numpy as np

from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.search.sampling import latin_hypercube

from . import assemble
from . import constraints as design_constraints
from .burmester import burmester_dyads
from .dyads import moving_pivots_for_ground
from .poses import as_poses, characteristic_length

PENALTY = 10.0  # weight of the assembly violation (a length) in the residual vector
CHUNK = 512  # population rows scored at once
SETTLE_STEP = 3e-5  # unit box: the final polish's difference step (kkt.slopes)
SETTLE_GAIN = 1e-9  # relative: the polished design may be this much worse (round-off)
CONSTRAINT_WEIGHTS = (1e1, 1e3, 1e5)  # penalty weights of a Grashof or window violation in the
# residual vector, each stiffer pass only while the polish leaves one (then the settle holds
# the binding ones exactly)


def default_bounds(poses):
    """(lo, hi) in PARAM_NAMES order from the poses: pivots within 4 L of the centroid,
    lengths in [0.05 L, 6 L], angles free (L = characteristic_length)."""
    poses = as_poses(poses)
    cen, L = poses[:, :2].mean(0), characteristic_length(poses)
    lo = np.array([cen[0] - 4 * L, cen[1] - 4 * L, -np.pi, .05 * L, .05 * L, .05 * L, .05 * L,
                   -4 * L, -4 * L, -np.pi])
    hi = np.array([cen[0] + 4 * L, cen[1] + 4 * L, np.pi, 6 * L, 6 * L, 6 * L, 6 * L,
                   4 * L, 4 * L, np.pi])
    return lo, hi


def box_sample(rng, count, lo, hi):
    """count points of the box [lo, hi] from the house Latin hypercube (search.sampling)."""
    return lo + latin_hypercube(rng, count, len(lo)) * (hi - lo)


def _scores(params, poses, signs, phi_grid, weight, input_angles):
    """Objective of each population row with its best phi per pose from phi_grid (free
    timing) or its prescribed angles; returns (objective (N,), phi (N, n))."""
    n = len(poses)
    obj = np.empty(len(params))
    best_phi = np.empty((len(params), n))
    for start in range(0, len(params), CHUNK):
        p = params[start:start + CHUNK]
        phis = phi_grid if input_angles is None else input_angles
        ach, valid = assemble.body_poses(p, phis, signs)  # (N, K, 3)
        dpos = ach[:, :, None, :2] - poses[None, None, :, :2]
        dang = kin.wrap(ach[:, :, None, 2] - poses[None, None, :, 2])
        cost = np.sum(dpos ** 2, -1) + (weight * dang) ** 2  # (N, K, n)
        cost = np.where(valid[:, :, None], cost, np.inf)
        if input_angles is None:
            k = np.argmin(cost, 1)
            obj[start:start + len(p)] = np.sum(np.take_along_axis(cost, k[:, None, :], 1)[:, 0], -1)
            best_phi[start:start + len(p)] = phi_grid[k]
        else:
            obj[start:start + len(p)] = np.sum(np.diagonal(cost, axis1=1, axis2=2), -1)
            best_phi[start:start + len(p)] = input_angles
    return np.where(np.isfinite(obj), obj, np.inf), best_phi


def residuals(x_full, poses, sign, weight, timing_angles):
    """Residual vectors [dx_i, dy_i, w dangle_i, PENALTY * violation_i] of designs
    x_full (..., 10 + n) (free timing: the n input angles) or (..., 11) (prescribed: one
    offset added to timing_angles); vectorized over the leading axes."""
    x_full = np.asarray(x_full, float)
    p = x_full[..., :10]
    phi = x_full[..., 10:] if timing_angles is None else timing_angles + x_full[..., 10:11]
    ach, _ = assemble.body_poses(p, phi, sign)
    a, b, c, d = (p[..., k, None] for k in (4, 5, 6, 3))
    rho = kin.ground_distance(a, d, phi)
    viol = np.maximum(0.0, np.maximum(rho - (b + c), np.abs(b - c) - rho))
    dpos = ach[..., :2] - poses[:, :2]
    dang = kin.wrap(ach[..., 2] - poses[:, 2])
    lead = x_full.shape[:-1]
    return np.concatenate([dpos.reshape(lead + (-1,)), weight * dang, PENALTY * viol], -1)


def central_jacobian(fun, z):
    """Jacobian of a row-vectorized fun by central differences, all 2 * dim points in one
    call; step h_k = eps^(1/3) max(1, |z_k|)."""
    h = np.finfo(float).eps ** (1 / 3) * np.maximum(1.0, np.abs(z))
    pts = np.concatenate([z + np.diag(h), z - np.diag(h)])
    f = fun(pts)
    dim = len(z)
    return ((f[:dim] - f[dim:]) / (2 * h[:, None])).T


def _starts(poses, lo, hi, rng, population, signs):
    """Population rows: LHS, Burmester linkages of 5-pose subsets, 3-pose inversions."""
    n = len(poses)
    rows = [box_sample(rng, population, lo, hi)]
    if n >= 5:
        subsets = [np.linspace(0, n - 1, 5).round().astype(int)]
        subsets += [np.sort(rng.choice(n, 5, replace=False)) for _ in range(3)]
        for sub in subsets:
            res = burmester_dyads(poses[sub])
            k = len(res.ground)
            if k >= 2:
                i, j = np.nonzero(~np.eye(k, dtype=bool))
                p, _, _ = assemble.dyad_pair_params(poses, res.ground[i], res.moving[i],
                                                    res.ground[j], res.moving[j])
                rows.append(p)
    if n >= 3:
        sub = np.array([0, n // 2, n - 1])
        pivots = box_sample(rng, population, lo, hi)
        g1 = pivots[:, :2]
        g2 = g1 + pivots[:, 3:4] * np.stack([np.cos(pivots[:, 2]), np.sin(pivots[:, 2])], -1)
        m1, s1 = moving_pivots_for_ground(poses[sub], g1)
        m2, s2 = moving_pivots_for_ground(poses[sub], g2)
        ok = ~s1 & ~s2
        p, _, _ = assemble.dyad_pair_params(poses, g1[ok], m1[ok], g2[ok], m2[ok])
        rows.append(p)
    allp = np.concatenate(rows)
    # angles into [-pi, pi]; rows outside the bounds are clipped into them
    allp[:, [2, 9]] = kin.wrap(allp[:, [2, 9]])
    allp = np.clip(allp[np.all(np.isfinite(allp), -1)], lo, hi)
    return allp


def solve_least_squares(poses, bounds=None, *, branch="either", timing="free",
                        input_angles=None, offset_bounds=(0.0, 0.0), angle_weight=None,
                        grashof=None, transmission=None, seed=0, population=2000,
                        polish=8, grid=180, budget=None) -> dict:
    """Best four-bar through `poses` (n, 3; angles rad) in the least-squares sense.

    bounds: (lo, hi) arrays (10,) in PARAM_NAMES order (lo == hi fixes a value), default
    default_bounds; branch "open" | "crossed" | "either"; timing "free" or "prescribed"
    with input_angles (n,) rad and offset_bounds (lo, hi) rad; grashof: a class name the
    design must have, or None; transmission (lo, hi) rad at every pose, or None.
    Returns dict: params (10,), branch, input_angles (n,), objective, achieved (n, 3),
    position_error (n,), angle_error (n,), checks (assemble.check_linkage), feasible,
    why (reason when not feasible), angle_weight, evaluations (objective evaluations),
    converged (the polish of the best met its tolerances), candidates (every polished
    design: params, branch, objective, defects). budget: a search.budget.Budget that counts
    the evaluations (a fresh one without a cap when None); the polishes stop at its cap."""
    from scipy.optimize import least_squares

    from linkcli.search.budget import Budget

    counter = budget if budget is not None else Budget(2**62)
    poses = as_poses(poses)
    n = len(poses)
    lo, hi = (np.asarray(v, float) for v in (bounds if bounds is not None else default_bounds(poses)))
    weight = characteristic_length(poses) if angle_weight is None else float(angle_weight)
    rng = np.random.default_rng(seed)
    prescribed = timing == "prescribed"
    t_angles = np.asarray(input_angles, float) if prescribed else None
    signs = {"open": [-1.0], "crossed": [1.0], "either": [-1.0, 1.0]}[branch]
    starts = _starts(poses, lo, hi, rng, population, signs)
    phi_grid = np.linspace(-np.pi, np.pi, grid, endpoint=False)
    pool = []
    for sign in signs:
        if prescribed:
            offs = np.linspace(offset_bounds[0], offset_bounds[1], 9 if offset_bounds[1] > offset_bounds[0] else 1)
            best = None
            for off in offs:
                sc, ph = _scores(starts, poses, sign, None, weight, t_angles + off)
                best = (sc, np.full(len(sc), off)) if best is None else (
                    np.where(sc < best[0], sc, best[0]), np.where(sc < best[0], off, best[1]))
                counter.add(len(starts))
            score, extra = best[0], best[1][:, None]
        else:
            score, extra = _scores(starts, poses, sign, phi_grid, weight, None)
            counter.add(len(starts) * grid)
        order = np.argsort(score, kind="stable")[:polish * 4]
        chosen = []
        for k in order:  # pick distinct starts (a short loop over the best few)
            if np.isfinite(score[k]) and all(np.linalg.norm((starts[k] - starts[c]) / (hi - lo + 1e-300)) > 1e-3 for c in chosen):
                chosen.append(k)
            if len(chosen) == polish:
                break
        for k in chosen:
            pool.append((sign, np.concatenate([starts[k], extra[k]])))
    free = hi > lo
    scale = characteristic_length(poses)
    grashof_held = grashof if grashof not in (None, "any") else None
    m_cons = design_constraints.count(grashof_held, transmission, n)

    def constraint_values(x):  # (..., m) g <= 0 feasible, length unit
        phi = x[..., 10:] if t_angles is None else t_angles + x[..., 10:11]
        return design_constraints.values(x, phi, grashof_held, transmission, scale)

    results, setups = [], []
    for sign, x0 in pool:
        if prescribed:
            tlo, thi = np.array([offset_bounds[0]]), np.array([offset_bounds[1]])
        else:
            tlo, thi = np.full(n, -4 * np.pi), np.full(n, 4 * np.pi)
        lo_full, hi_full = np.concatenate([lo, tlo]), np.concatenate([hi, thi])
        mask = np.concatenate([free, thi > tlo])
        x0 = np.clip(x0, lo_full, hi_full)

        def design(z, x0=x0):
            z = np.asarray(z, float)
            x = np.broadcast_to(x0, z.shape[:-1] + x0.shape).copy()
            x[..., mask] = z
            return x

        def fun(z, sign=sign):
            return residuals(design(z), poses, sign, weight, t_angles)

        def cons(z):
            return constraint_values(design(z))

        z0 = x0[mask]
        span = hi_full[mask] - lo_full[mask]
        z0 = np.clip(z0, lo_full[mask] + 1e-12 * span, hi_full[mask] - 1e-12 * span)
        passes = [None] + (list(CONSTRAINT_WEIGHTS) if m_cons else [])
        penalized = False
        for penalty in passes:  # unconstrained first; stiffer penalties while one is broken
            if penalty is not None and np.all(cons(z0) <= 0.0):
                break
            penalized = penalty is not None

            def penalized(z, penalty=penalty):
                r = fun(z)
                return r if penalty is None else np.concatenate([r, penalty * np.maximum(0.0, cons(z))], -1)

            sol = least_squares(penalized, z0, jac=lambda z, f=penalized: central_jacobian(f, z),
                                bounds=(lo_full[mask], hi_full[mask]), method="trf",
                                xtol=1e-15, ftol=1e-15, gtol=1e-15,
                                max_nfev=max(1, min(400 * (len(z0) + 1), counter.left // (2 * len(z0) + 1))))
            counter.add(sol.nfev + 2 * len(z0) * (sol.njev or 0))  # a Jacobian costs 2 dim evaluations
            z0 = sol.x
        x = x0.copy()
        x[mask] = z0
        results.append(_evaluate(x, poses, sign, weight, t_angles, grashof, transmission))
        results[-1]["converged"] = bool(sol.status > 0)
        results[-1]["penalized"] = penalized
        setups.append((fun, cons if m_cons else None, x, mask, lo_full, hi_full, sign, scale))
    order = sorted(range(len(results)), key=lambda i: (not results[i]["feasible"], results[i]["objective"]))
    # the best is settled; with constraints every candidate is (a penalty polish ends at a
    # point whose last digits follow round-off, and the candidates are listed)
    for i in (order if m_cons else order[:1]):
        if not (results[i]["feasible"] or m_cons):
            continue
        settled = _settle(counter, *setups[i])
        if settled is not None:
            out = _evaluate(settled, poses, setups[i][6], weight, t_angles, grashof, transmission)
            if out["feasible"] and (not results[i]["feasible"] or
                                    out["objective"] <= results[i]["objective"] * (1.0 + SETTLE_GAIN)):
                out["converged"] = out["settled"] = True
                results[i] = out
    order = sorted(range(len(results)), key=lambda i: (not results[i]["feasible"], results[i]["objective"]))
    if m_cons:  # listed: the best, and the others unless a penalty pass ended them and the
        # final polish did not settle them (their last digits follow round-off along the penalty)
        order = order[:1] + [i for i in order[1:]
                             if results[i].get("settled") or not results[i].get("penalized")]
    ranked = [results[i] for i in order]
    best = dict(ranked[0])
    best["angle_weight"] = weight
    best["evaluations"] = counter.used
    best["candidates"] = [{k: r[k] for k in ("params", "branch", "objective", "feasible", "why")}
                          for r in ranked]
    return best


def _settle(counter, fun, cons, x, mask, lo, hi, sign, scale):
    """The best polished design after the final polish (linkcli.search.kkt): Gauss-Newton
    on its residuals in the unit box of its free variables, the bounds and the constraints
    (`cons`, g <= 0, or None) that bind held, to round-off, so that the printed digits are
    the optimum's and not those of least_squares' path (its SVD follows the BLAS kernel).
    A penalty polish ends just outside a binding constraint; here it binds exactly. None
    when it does not converge or the budget has no room (evaluations counted against
    `counter`)."""
    from linkcli.search import kkt, linalg
    from linkcli.search.budget import BudgetSpent

    width = hi[mask] - lo[mask]

    def values(u):
        counter.spend(len(u))
        z = lo[mask] + np.clip(u, 0.0, 1.0) * width
        r = fun(z)
        return r if cons is None else np.concatenate([r, -cons(z) / scale], -1)

    m = len(fun(x[mask]))

    def evaluate(u):
        v, jac = kkt.slopes(values, u, step=SETTLE_STEP)
        r, jr = v[:m], jac[:m]
        return kkt.Point(float(linalg.dot(r, r)), 2.0 * linalg.matvec(jr.T, r), v[m:], jac[m:],
                         h=2.0 * linalg.gram(jr))

    try:
        out = kkt.settle(evaluate, (x[mask] - lo[mask]) / width)
    except BudgetSpent:
        return None
    if not out.converged:
        return None
    x = x.copy()
    x[mask] = lo[mask] + out.u * width
    return x


def _evaluate(x, poses, sign, weight, t_angles, grashof, transmission) -> dict:
    p = x[:10]
    phi = kin.wrap(x[10:] if t_angles is None else t_angles + x[10])
    ach, valid = assemble.body_poses(p, phi, sign)
    pos, ang = assemble.pose_errors(poses, ach)
    objective = float(np.sum(pos ** 2 + (weight * ang) ** 2))
    checks = assemble.check_linkage(p[4], p[5], p[6], p[3], phi, np.full(len(phi), sign))
    why = []
    if not np.all(valid):
        why.append("does not assemble at every pose")
    why += [f"{d} defect" for d in checks["defects"]]
    if grashof is not None and checks["grashof"]["class"] != grashof:
        why.append(f"Grashof class {checks['grashof']['class']}, not {grashof}")
    if transmission is not None and (checks["transmission_min"] < transmission[0]
                                     or checks["transmission_max"] > transmission[1]):
        why.append("transmission angle outside its bounds")
    return {"params": p, "branch": "open" if sign < 0 else "crossed", "input_angles": phi,
            "objective": objective, "achieved": ach, "position_error": pos, "angle_error": ang,
            "checks": checks, "feasible": not why, "why": "; ".join(why)}
