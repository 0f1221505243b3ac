"""Local solver for constrained nonlinear least squares in the unit box (scipy, lazily).

    minimize f(u) = |r(u)|^2   subject to   c(u) >= 0,   0 <= u <= 1

The problem is an object with `n_variables`, `weight` (of the L1 merit
f + weight * sum(max(0, -c))), `value(u) -> (f, c, r, ...)` and
`slope(u, central=True) -> (grad f, dc/du, dr/du)` (central=False: a cheaper one-sided
estimate, enough for the Gauss-Newton model); it may raise any exception to stop (a spent
evaluation budget), which passes through.

Two stages, because the minima of such objectives often lie in long curved valleys where
a quasi-Newton model started from the identity needs hundreds of iterations:

1. `gauss_newton`: sequential quadratic programming with the Gauss-Newton Hessian, a
   constrained Levenberg-Marquardt method, with second-order corrections so that steps
   along a curved active constraint are not rejected (the Maratos effect). Each
   subproblem is a least-distance problem solved exactly by NNLS (`least_distance`).
2. `slsqp_rounds`: scipy SLSQP in coordinates where the Gauss-Newton Hessian is the
   identity, from where stage 1 ended, to certify a KKT point (often in one iteration).

References: Lawson & Hanson, "Solving Least Squares Problems" (1974), ch. 23 (LDP);
Nocedal & Wright, "Numerical Optimization" (2006), ch. 10 (Levenberg-Marquardt) and
18.3 (second-order correction); Kraft (1988), DFVLR-FB 88-28 (SLSQP).
"""

from __future__ import annotations

import numpy as np

GN_ITERATIONS = 1000  # Gauss-Newton steps at most (long curved valleys need hundreds)
GN_TRIALS = 12  # damping increases tried for one step
GN_STEP = 1e-12  # a step this small (unit box) ends stage 1
GN_GAIN = 1e-10  # relative: a merit gain this small ends stage 1
ACCEPT = 0.25  # a step is taken when the merit falls by this share of the prediction
SLSQP_ITERATIONS = 60  # per round of stage 2
SLSQP_ROUNDS = 4
REGULARIZE = 1e-9  # relative ridge on the Gauss-Newton Hessian of stage 2
FTOL = 1e-11  # SLSQP's tolerance, relative to the objective where stage 2 starts,
FTOL_ABS = 1e-13  # and at least this (SLSQP applies it to the constraints' violation too)
STALL = 1e-10  # relative: a round of stage 2 that gains less has stalled
FEASIBLE = 1e-8  # constraint violation accepted at a stalled, stationary point


def polish(problem, u0: np.ndarray, gauss_newton_first: bool = True) -> bool:
    """Both stages from u0 (stage 1 optional); True if SLSQP certified the end point.
    Arithmetic that overflows (absurd bounds) ends the search early, not with an error:
    the best point evaluated so far stands."""
    u = np.clip(np.asarray(u0, dtype=float), 0.0, 1.0)
    try:
        with np.errstate(all="ignore"):
            if gauss_newton_first:
                u = gauss_newton(problem, u)
            return slsqp_rounds(problem, u)
    except (ArithmeticError, ValueError, np.linalg.LinAlgError):
        return False


def least_distance(g: np.ndarray, h: np.ndarray, nnls=None) -> np.ndarray | None:
    """min |w| subject to g w >= h, or None when the constraints are inconsistent.

    Lawson & Hanson (1974), ch. 23: with E = [g^T; h^T] and f = (0, ..., 0, 1), solve the
    NNLS problem min |E y - f|, y >= 0; the residual r = E y - f vanishes only if no w
    exists, else w = -r[:n] / r[n]. `nnls`: the NNLS solver (scipy.optimize.nnls when None;
    linkcli.search.nnls.nnls keeps scipy unloaded)."""
    if nnls is None:
        from scipy.optimize import nnls as scipy_nnls
        nnls = scipy_nnls
    n = g.shape[1]
    e = np.vstack([g.T, h[None, :]])
    f = np.zeros(n + 1)
    f[-1] = 1.0
    try:
        y, _ = nnls(e, f, maxiter=50 * max(e.shape))
    except RuntimeError:
        return None
    r = e @ y - f
    if not np.all(np.isfinite(r)) or r[n] > -1e-12:
        return None
    return -r[:n] / r[n]


def gauss_newton(problem, u0: np.ndarray, nnls=None) -> np.ndarray:
    """Stage 1; returns the last accepted point (`nnls`: least_distance's solver).

    At u, with J = dr/du and A = dc/du (the box among the constraints), the step solves

        min |r + J s|^2 + mu s^T D s   subject to   c + A s >= 0,   D = diag(J^T J);

    with R^T R = 2 (J^T J + mu D) and z = R s it is the least-distance problem
    min |z + R^-T grad f| subject to A R^-1 z >= -c. The step is taken when the merit
    falls by at least ACCEPT of the model's prediction (after a second-order correction
    if needed: the same problem with c replaced by c(u + s) - A s), and Marquardt's mu
    shrinks or grows with the agreement."""
    n = problem.n_variables
    eye = np.eye(n)
    box = np.vstack([eye, -eye])
    weight = problem.weight
    u = np.clip(np.asarray(u0, dtype=float), 0.0, 1.0)

    def merit(x):
        f, c = problem.value(x)[:2]
        return f + weight * float(np.sum(np.maximum(0.0, -c)))

    mu = 1e-3
    m_u = merit(u)
    for _ in range(GN_ITERATIONS):
        _, cons, res = problem.value(u)[:3]
        _, jc, jr = problem.slope(u, central=False)
        if not (_finite(cons, res, jc, jr)):
            return u  # slopes that overflow (absurd bounds): nothing to build a model from
        jtj = jr.T @ jr
        a = np.vstack([jc, box])
        c = np.concatenate([cons, u, 1.0 - u])
        grad = 2.0 * jr.T @ res
        violation = weight * float(np.sum(np.maximum(0.0, -cons)))
        for _ in range(GN_TRIALS):
            h = 2.0 * (jtj + mu * np.diag(np.diag(jtj))) + 1e-12 * max(float(np.trace(jtj)), 1e-300) * eye
            try:
                r_inv = np.linalg.inv(np.linalg.cholesky(h).T)  # s = r_inv @ z
            except np.linalg.LinAlgError:
                return u
            b = r_inv.T @ grad  # 1/2 |z|^2 + b.z = 1/2 |z + b|^2 + const
            g = a @ r_inv
            if not _finite(b, g, g @ b):
                return u
            w = least_distance(g, -c + g @ b, nnls)
            if w is None:
                return u
            step = r_inv @ (w - b)
            trial = np.clip(u + step, 0.0, 1.0)
            predicted = -(grad @ step + 0.5 * step @ h @ step) + violation
            m_trial = merit(trial)
            if predicted <= 0.0 or np.max(np.abs(step)) < GN_STEP:
                return trial if m_trial < m_u else u
            ratio = (m_u - m_trial) / predicted
            if ratio <= ACCEPT and len(cons):
                shifted = np.concatenate([problem.value(trial)[1] - jc @ step, u, 1.0 - u])
                w = least_distance(g, -shifted + g @ b, nnls)
                if w is not None:
                    corrected = np.clip(u + r_inv @ (w - b), 0.0, 1.0)
                    m_corr = merit(corrected)
                    if (m_u - m_corr) / predicted > ratio:
                        trial, m_trial, ratio = corrected, m_corr, (m_u - m_corr) / predicted
            if ratio > ACCEPT:
                gain = m_u - m_trial
                u, m_u = trial, m_trial
                if ratio > 0.75:
                    mu /= 3.0
                break
            mu *= 4.0
        else:
            return u
        if gain <= GN_GAIN * max(abs(m_u), 1e-300):
            return u
    return u


def slsqp_rounds(problem, u0: np.ndarray) -> bool:
    """Stage 2: SLSQP with the constraints explicit; True if it converged.

    Each round changes variables to z, u = u_r + R^-1 z with R^T R = J^T J + lambda I the
    Gauss-Newton Hessian where the round starts, so that SLSQP's initial quasi-Newton
    model (the identity) is already right; the box becomes linear inequalities on z.
    Up to SLSQP_ROUNDS rounds, each restarted where the last ended. A round that ends,
    feasible, where it began is at a point that rounding keeps SLSQP from certifying:
    another round cannot move it, and it counts as converged."""
    from scipy.optimize import minimize
    n = problem.n_variables
    eye = np.eye(n)
    u = np.clip(np.asarray(u0, dtype=float), 0.0, 1.0)
    f_round = problem.value(u)[0]
    ftol = max(FTOL * f_round, FTOL_ABS)
    for _ in range(SLSQP_ROUNDS):
        grad, jc, jr = problem.slope(u)
        if not _finite(grad, jc, jr):
            return False
        h = jr.T @ jr
        h += (REGULARIZE * max(float(np.max(np.diag(h))), 0.0) + 1e-300) * eye
        try:
            r_inv = np.linalg.inv(np.linalg.cholesky(h).T)
        except np.linalg.LinAlgError:
            return False
        base = u.copy()
        box = np.vstack([r_inv, -r_inv])
        lim = np.concatenate([base, 1.0 - base])
        cons = [{"type": "ineq", "fun": lambda z: problem.value(base + r_inv @ z)[1],
                 "jac": lambda z: problem.slope(base + r_inv @ z)[1] @ r_inv},
                {"type": "ineq", "fun": lambda z: box @ z + lim, "jac": lambda z: box}]
        try:
            res = minimize(lambda z: problem.value(base + r_inv @ z)[0], np.zeros(n),
                           jac=lambda z: r_inv.T @ problem.slope(base + r_inv @ z)[0],
                           method="SLSQP", constraints=cons,
                           options={"maxiter": SLSQP_ITERATIONS, "ftol": ftol})
        except ValueError:  # a non-finite value reached SLSQP
            return False
        u = np.clip(base + r_inv @ res.x, 0.0, 1.0)
        f_end, c_end = problem.value(u)[:2]  # the end point is evaluated (and recorded)
        if res.success:
            return True
        if f_end >= f_round * (1.0 - STALL) and np.min(c_end, initial=0.0) >= -FEASIBLE:
            return True
        f_round = f_end
    return False


def _finite(*arrays) -> bool:
    return all(bool(np.all(np.isfinite(x))) for x in arrays)
