"""Closed-form Jacobians for the path search (numpy only): the target errors, projected
(`projected_jacobian`) or on every variable (`full_jacobian`), and the penalties
(`penalty_jacobian`).

With the coupler point p = px + i py and the ground pivot G = gx + i gy solved for by
linear least squares (`starts.fit_linear`), the target errors r_k = P_k - T_k are a
function of the other variables z alone (lengths, ground angle gamma, timing):

    P_k = G + w (a e^{i phi_k} + E_k p),   w = e^{i gamma},  E_k = e^{i theta_k},
    r(z) = P_perp(z) (f(z) - T),   A = [w E_k, i w E_k, 1, i] (the free linear columns),

and its exact derivative (Golub & Pereyra 1973, SIAM J. Numer. Anal. 10; Kaufman 1975,
BIT 15, drops the second term) is

    dr/dz_v = P_perp D_v - A (A^T A)^{-1} (dA/dz_v)^T r,

with D_v = dP/dz_v at fixed (p, G). The coupler angle's slopes come from the loop
a e^{i phi} + b e^{i theta} = d + c e^{i psi} differentiated with psi eliminated
(Norton, Design of Machinery, ch. 6):

    theta_v = Re(F_v e^{-i psi}) / (b sin(theta - psi)),
    F_a = e^{i phi}, F_phi = i a e^{i phi}, F_b = e^{i theta}, F_c = -e^{i psi}, F_d = -1.

A linear variable that `fit_linear` holds at a bound is a constant (its column leaves A).
Complex numbers stand for the (x, y) pairs; rows of the real Jacobian interleave them
like the residuals (x_1, y_1, x_2, ...). Linear systems by `linkcli.search.linalg`.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.search import linalg
from linkcli.types.path_generation.model import GRASHOF_MARGIN, N_LINK, SHORTEST, Design, rho2_extremes
from linkcli.types.path_generation.starts import linear_normal, linear_pair

LINEAR = [4, 5, 6, 7]  # px, py, gx, gy: linear in the coupler point once the rest is set
DEAD = 1e-6  # |sin(theta - psi)| below this at a target: the slopes are not trusted there


class _Slopes:
    """The coupler point's slopes at fixed (p, G) along the nonlinear variables `idx`
    (in their order), dp (N, n, k) complex, and the coupler angle's, dtheta (N, n, k);
    with what the projection reuses."""

    def __init__(self, design: Design, idx, x: np.ndarray, pose, s) -> None:
        n_rows, n = len(x), design.n_targets
        a, b = x[:, 1:2], x[:, 2:3]
        p = x[:, 4:5] + 1j * x[:, 5:6]
        self.w = w = np.exp(1j * x[:, 8:9])
        e_phi = pose.cphi + 1j * pose.sphi
        self.e_theta = e_theta = pose.ct + 1j * pose.st
        e_psi = pose.cpsi + 1j * pose.spsi
        sin_tp = pose.st * pose.cpsi - pose.ct * pose.spsi  # sin(theta - psi)
        self.ok = np.all(pose.valid, axis=1) & np.all(np.abs(sin_tp) > DEAD, axis=1)
        den = b * np.where(np.abs(sin_tp) > DEAD, sin_tp, DEAD)
        turn = np.conj(e_psi)

        def theta_slope(force):  # theta_v for the loop's partial F_v
            return (force * turn).real / den

        self.crank = crank = a * e_phi
        self.arm = arm = e_theta * p  # E_k p
        slopes = {0: theta_slope(-np.ones_like(crank)), 1: theta_slope(e_phi),
                  2: theta_slope(e_theta), 3: theta_slope(-e_psi)}
        t_phi = theta_slope(1j * crank)
        d_point = {j: w * 1j * arm * slopes[j] for j in (0, 2, 3)}
        d_point[1] = w * (e_phi + 1j * arm * slopes[1])
        d_point[8] = 1j * w * (crank + arm)
        slopes[8] = np.zeros_like(t_phi)
        d_phi = w * 1j * (crank + arm * t_phi)  # dP_k / dphi_k
        self.t_phi, self.d_phi = t_phi, d_phi
        link = [j for j in idx if j < N_LINK]
        self.dp = np.stack([d_point[j] for j in link], axis=2) if link else np.zeros((n_rows, n, 0), complex)
        self.dtheta = np.stack([slopes[j] for j in link], axis=2) if link else np.zeros((n_rows, n, 0))
        timing = [j for j in idx if j >= N_LINK]
        if timing:
            dphi = _phi_slopes(design, np.array(timing), s, n)  # (N, n, t)
            self.dp = np.concatenate([self.dp, d_phi[:, :, None] * dphi], axis=2)
            self.dtheta = np.concatenate([self.dtheta, t_phi[:, :, None] * dphi], axis=2)


def _real(design: Design, jac: np.ndarray, ok: np.ndarray):
    """Complex slopes (N, n, k) as the residuals' real rows (x_1, y_1, ...) / L, and
    which rows hold (finite, `_Slopes.ok`)."""
    n_rows, n = jac.shape[:2]
    out = np.stack([jac.real, jac.imag], axis=2).reshape(n_rows, 2 * n, -1) / design.scale
    return out, ok & np.all(np.isfinite(out), axis=(1, 2))


def full_jacobian(design: Design, idx: np.ndarray, x: np.ndarray, pose, s):
    """(N, 2n, k) Jacobian of the target errors / L with respect to the variables `idx`
    (any of them), linear ones included (columns w E_k, i w E_k, 1, i), at full vectors
    x (N, nx) with their pose; and (N,) whether each row's slopes hold (as
    `projected_jacobian`)."""
    linear = {4: lambda sl: sl.w * sl.e_theta, 5: lambda sl: 1j * sl.w * sl.e_theta,
              6: lambda sl: np.ones_like(sl.e_theta), 7: lambda sl: np.full_like(sl.e_theta, 1j)}
    nonlinear = [j for j in idx if j not in linear]
    sl = _Slopes(design, nonlinear, x, pose, s)
    cols, k = [], 0
    for j in idx:
        if j in linear:
            cols.append(linear[j](sl))
        else:
            cols.append(sl.dp[:, :, k])
            k += 1
    jac = np.stack(cols, axis=2) if cols else np.zeros(sl.e_theta.shape + (0,), complex)
    return _real(design, jac, sl.ok)


def projected_jacobian(design: Design, idx: np.ndarray, x: np.ndarray, pose, sign, s):
    """(N, 2n, k) Jacobian of the target errors / L with respect to the variables `idx`
    (none of them linear) at full vectors x (N, nx) whose linear part `fit_linear` has
    just solved, with that fit's pose; and (N,) whether each row's slopes hold (the
    linkage assembles at every target, away from a dead point: elsewhere the caller
    takes differences)."""
    sl = _Slopes(design, idx, x, pose, s)
    gamma_col = np.array([j == 8 for j in idx], dtype=float)
    # the linear columns (px, py, gx, gy) are w E_k, i w E_k, 1, i (their real inner
    # products: n on the diagonal, sigma = sum w E_k off it, as in fit_linear); the slopes
    # of the first two, i (theta_v + gamma_v) w E_k; the pivot's are constant
    we = sl.w * sl.e_theta
    d_px = we[:, :, None] * (1j * (sl.dtheta + gamma_col[None, None, :]))
    r = _errors(design, x, sl)
    # (dA_v)^T r for the px and py columns: Re and Im of sum conj(d(w E_k)) r
    cross = np.sum(np.conj(d_px) * r[:, :, None], axis=1)
    along = np.sum(np.conj(we)[:, :, None] * sl.dp, axis=1)  # A^T D: px, py columns
    plain = np.sum(sl.dp, axis=1)  # gx, gy columns
    coef = _coefficients(design, x, we, np.stack([along.real + cross.real, along.imag + cross.imag,
                                                  plain.real, plain.imag], axis=1))
    fitted = we[:, :, None] * (coef[:, None, 0] + 1j * coef[:, None, 1]) + (coef[:, None, 2]
                                                                          + 1j * coef[:, None, 3])
    return _real(design, sl.dp - fitted, sl.ok)


def increments_parts(design: Design, idx: np.ndarray, x: np.ndarray, pose, sign, s):
    """The projected Jacobian of the target errors / L in the factors of
    linkcli.search.increments, the timing in each target's own input angle phi_k (not yet
    the increments): (w (N, 2n, p): the link columns `idx` as `projected_jacobian`;
    local (N, 2n): target k's rows' slopes along phi_k; a (N, 2n, 4): the linear columns
    w E_k, i w E_k, 1, i / L; coef (N, 4, n): the projection's coefficients of each phi_k),
    the angle columns being local - a coef; and (N,) whether the rows' slopes hold. Each
    phi_k moves target k alone, so every sum over the targets of `projected_jacobian`
    is one term here: O(n) in all."""
    link = np.array([j for j in idx if j < N_LINK], dtype=int)
    w_part, ok = projected_jacobian(design, link, x, pose, sign, s)
    sl = _Slopes(design, [], x, pose, s)
    we = sl.w * sl.e_theta
    r = _errors(design, x, sl)
    cross = np.conj(we * 1j * sl.t_phi) * r  # (dA_k)^T r: target k's term alone
    along = np.conj(we) * sl.d_phi
    coef = _coefficients(design, x, we, np.stack([along.real + cross.real, along.imag + cross.imag,
                                                  sl.d_phi.real, sl.d_phi.imag], axis=1))
    n_rows, n = we.shape
    local = np.stack([sl.d_phi.real, sl.d_phi.imag], axis=2).reshape(n_rows, 2 * n) / design.scale
    columns = np.stack([we, 1j * we, np.ones_like(we), np.full_like(we, 1j)], axis=2)  # (N, n, 4)
    a = np.stack([columns.real, columns.imag], axis=2).reshape(n_rows, 2 * n, 4) / design.scale
    return w_part, local, a, coef, ok & np.all(np.isfinite(local), axis=1)


def _errors(design: Design, x: np.ndarray, sl: _Slopes) -> np.ndarray:
    """The target errors P_k - T_k (N, n) complex, from the slopes' closure."""
    targets = design.targets[:, 0] + 1j * design.targets[:, 1]
    return (x[:, 6:7] + 1j * x[:, 7:8]) + sl.w * (sl.crank + sl.arm) - targets


def _coefficients(design: Design, x: np.ndarray, we: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """(A^T A)^-1 (A^T D + (dA)^T r) (N, 4, cols) from its right-hand side rhs (N, 4, cols)
    (real parts: px, py, gx, gy), over the linear columns the fit solved for (`_unheld`;
    the others 0): all four free, fit_linear's complex 2 x 2 in closed form; else the
    4 x 4 system."""
    n_rows = len(x)
    free = _unheld(design, x)  # (N, 4)
    sigma = np.sum(we, axis=1)
    n = float(design.n_targets)
    s1, s2 = rhs[:, 0] + 1j * rhs[:, 1], rhs[:, 2] + 1j * rhs[:, 3]
    point, pivot, posed = linear_pair(n, sigma[:, None], s1, s2)
    closed = np.all(free, axis=1) & posed[:, 0]
    coef = np.empty((n_rows, 4, rhs.shape[2]))
    coef[closed] = np.stack([point.real, point.imag, pivot.real, pivot.imag], axis=1)[closed]
    rest = np.flatnonzero(~closed)
    if len(rest):  # a linear variable held at its bound, or an ill-posed fit
        fr = free[rest]
        coef[rest] = linalg.solve_spd(linalg.restricted(linear_normal(n, sigma[rest]), fr),
                                      np.where(fr[:, :, None], rhs[rest], 0.0))
    return coef


def _phi_slopes(design: Design, timing: np.ndarray, s, n: int) -> np.ndarray:
    """d phi_k / d x_j (N, n, t) for the timing variables j (t of them, ascending): the
    offset or the first angle moves every target's input angle; the increment delta_m
    (j = N_LINK + m - 1) those from target m on, in the turning direction s."""
    if design.timing == "prescribed":
        return np.ones((len(s), n, len(timing)))
    first = timing - N_LINK  # the first target (0-based) each variable moves
    return np.where(np.arange(n)[:, None] >= first[None, :], 1.0, 0.0)[None] * \
        np.where(timing == N_LINK, 1.0, s[:, None])[:, None, :]


def _unheld(design: Design, x: np.ndarray) -> np.ndarray:
    """(N, 4) the linear variables (px, py, gx, gy) the fit solved for: free and not
    held at a bound."""
    cols = list(LINEAR)
    lo, hi = design.lo[cols], design.hi[cols]
    v = x[:, cols]
    return (hi > lo)[None, :] & (v > lo) & (v < hi)


def penalty_jacobian(design: Design, idx, x: np.ndarray, frame, s, weight: float, violated):
    """(N, m, k) slopes of the penalty residuals weight * max(0, g) / L (`Design.penalties`,
    columns in the order of `Design.constraints`) along the variables `idx`: the slope of
    g where it is `violated` (N, m: the penalty residuals are positive; Gauss-Newton on a
    one-sided penalty), 0 elsewhere. frame: the closure at x (`closure.Frame`: rho = |A B0|
    and the crank's direction at the targets). Slopes of the constraint functions:

        Grashof rows: +-1 for each link, plus the margin's share of the total;
        cos mu(r2) = (b^2 + c^2 - r2) / (2 b c): d/db = (b^2 - c^2 + r2) / (2 b^2 c),
            d/dc = (c^2 - b^2 + r2) / (2 b c^2), d/dr2 = -1 / (2 b c);
        r2 = a^2 + d^2 - 2 a d cos(phi) at the span's end that holds the extreme (or
            (a -+ d)^2 at phi = 0, pi): d/da = 2 (a - d cos phi), d/dd = 2 (d - a cos phi),
            d/dphi = 2 a d sin phi;
        assembly: |b - c| - rho_k or rho_k - (b + c), whichever is larger, with
            d rho_k = (a - d cos phi_k) / rho_k da + (d - a cos phi_k) / rho_k dd
                      + a d sin phi_k / rho_k dphi_k;
        the dead points: |b - c| - rho or rho - (b + c), rho = |a - d| or a + d;
        the sweep: L per increment."""

    n_rows, n = len(x), design.n_targets
    idx = list(idx)
    k = len(idx)
    d, a, b, c = (x[:, j] for j in range(4))
    phi = design.input_angles(x, s)
    unit = np.zeros((4, k))  # d(link)/dz for the links d, a, b, c
    for j in range(4):
        if j in idx:
            unit[j, idx.index(j)] = 1.0
    timing = [j for j in idx if j >= N_LINK]
    dphi = np.zeros((n_rows, n, k))
    if timing:
        dphi[:, :, k - len(timing):] = _phi_slopes(design, np.array(timing), s, n)
    rows = []
    rho, cphi, sphi = frame.rho, frame.cphi, frame.sphi
    margin = GRASHOF_MARGIN * unit.sum(axis=0)
    if design.grashof in SHORTEST:
        short = SHORTEST[design.grashof]
        others = [j for j in range(4) if j != short]
        for j in others:
            rest = [o for o in others if o != j]
            rows.append(np.broadcast_to(unit[short] + unit[j] - unit[rest[0]] - unit[rest[1]] + margin,
                                        (n_rows, k)))
    elif design.grashof == "triple-rocker":
        order = np.argsort(np.stack([d, a, b, c], axis=1), axis=1, kind="stable")
        sign = np.zeros((n_rows, 4))
        np.put_along_axis(sign, order, np.array([-1.0, 1.0, 1.0, -1.0])[None, :], axis=1)
        rows.append(np.einsum("nj,jk->nk", sign, unit, optimize=False) + margin)
    if design.window is not None:
        bc = 2.0 * b * c
        for end, at_lo in ((0, True), (1, False)):
            dr2 = _r2_slopes(design, a, d, phi, dphi, unit, at_lo)
            r2 = ((d - a) ** 2 if at_lo else (d + a) ** 2) if design.full_turn else \
                rho2_extremes(a, d, phi.min(axis=1), phi.max(axis=1) - phi.min(axis=1))[end]
            dcos = (((b * b - c * c + r2) / (b * bc))[:, None] * unit[2]
                    + ((c * c - b * b + r2) / (c * bc))[:, None] * unit[3] - dr2 / bc[:, None])
            rows.append(design.scale * (dcos if at_lo else -dcos))
    sbc = np.sign(b - c)[:, None]
    below = (sbc * (unit[2] - unit[3]))  # d|b - c|
    above = np.broadcast_to(unit[2] + unit[3], (n_rows, k))  # d(b + c)
    safe = np.where(rho > 0, rho, 1.0)
    drho = ((a[:, None] - d[:, None] * cphi) / safe)[:, :, None] * unit[1] + \
        ((d[:, None] - a[:, None] * cphi) / safe)[:, :, None] * unit[0] + \
        (a[:, None] * d[:, None] * sphi / safe)[:, :, None] * dphi
    short_side = (np.abs(b - c)[:, None] - rho) >= (rho - (b + c)[:, None])
    assembly = np.where(short_side[:, :, None], below[:, None, :] - drho, drho - above[:, None, :])
    out = np.concatenate([np.stack(rows, axis=1) if rows else np.zeros((n_rows, 0, k)), assembly], axis=1)
    dead = []
    for rho_at, drho_at in ((np.abs(a - d), np.sign(a - d)[:, None] * (unit[1] - unit[0])),
                            (a + d, np.broadcast_to(unit[0] + unit[1], (n_rows, k)))):
        first = (np.abs(b - c) - rho_at) >= (rho_at - (b + c))
        dead.append(np.where(first[:, None], below - drho_at, drho_at - above))
    out = np.concatenate([out, np.stack(dead, axis=1)], axis=1)
    if design.timing == "free":
        sweep = np.array([design.scale if j > N_LINK else 0.0 for j in idx])
        out = np.concatenate([out, np.broadcast_to(sweep, (n_rows, 1, k))], axis=1)
    out = np.where(violated[:, :, None], out, 0.0) * (weight / design.scale)
    return np.nan_to_num(out)


def _r2_slopes(design: Design, a, d, phi, dphi, unit, lowest: bool) -> np.ndarray:
    """(N, k) slopes of rho^2's smallest (or largest) value over the full turn or the
    targets' span (`model.rho2_extremes`)."""
    if design.full_turn:
        sgn = -1.0 if lowest else 1.0  # (d - a)^2 or (d + a)^2
        return 2.0 * (d + sgn * a)[:, None] * (unit[0] + sgn * unit[1])
    holds, target, p = _span_extreme(a, d, phi, lowest)
    rows = np.arange(len(a))
    slope = (2.0 * (a - d * np.cos(p)))[:, None] * unit[1] + (2.0 * (d - a * np.cos(p)))[:, None] * unit[0] \
        + (2.0 * a * d * np.sin(p))[:, None] * dphi[rows, target]
    sgn = -1.0 if lowest else 1.0
    extreme = 2.0 * (d + sgn * a)[:, None] * (unit[0] + sgn * unit[1])
    return np.where(holds[:, None], extreme, slope)


def _span_extreme(a, d, phi, lowest: bool):
    """Where rho^2 = a^2 + d^2 - 2 a d cos(phi) is smallest (or largest) over the targets'
    span: (N,) whether at phi = 0 (or pi) inside it, else the end target holding it and its
    angle."""
    lo = phi.min(axis=1)
    width = phi.max(axis=1) - lo
    at = math.pi if not lowest else 0.0
    holds = np.mod(at - lo, 2.0 * math.pi) <= width
    ends = np.stack([np.argmin(phi, axis=1), np.argmax(phi, axis=1)], axis=1)  # (N, 2) targets
    pe = np.take_along_axis(phi, ends, axis=1)
    r2 = a[:, None] ** 2 + d[:, None] ** 2 - 2 * a[:, None] * d[:, None] * np.cos(pe)
    pick = np.argmin(r2, axis=1) if lowest else np.argmax(r2, axis=1)
    rows = np.arange(len(a))
    return holds, ends[rows, pick], pe[rows, pick]


def penalty_angle_parts(design: Design, x: np.ndarray, frame, s, weight: float, violated):
    """The penalties' slopes along each target's own input angle phi_k (free timing, the
    factors of linkcli.search.increments; `penalty_jacobian` has them along the
    increments): (local (N, m): row k of the assembly's slope along phi_k, a d sin phi_k /
    rho_k with the side's sign, 0 on the other rows; [(row, slopes (N, n)), ...] of the
    rows several angles move: the window's over the targets' span, at its end target
    (2 a d sin phi / (2 b c), scaled as the row), and the sweep, s L (phi_n - phi_1)),
    weighted and 0 where the row is not `violated` (N, m), as `penalty_jacobian`."""
    n_rows, n = len(x), design.n_targets
    d, a, b, c = (x[:, j] for j in range(4))
    phi = design.input_angles(x, s)
    lead = (3 if design.grashof in SHORTEST else 1 if design.grashof == "triple-rocker" else 0)
    window = 2 if design.window is not None else 0
    local = np.zeros(violated.shape)
    rho = frame.rho
    safe = np.where(rho > 0, rho, 1.0)
    drho = a[:, None] * d[:, None] * frame.sphi / safe
    short_side = (np.abs(b - c)[:, None] - rho) >= (rho - (b + c)[:, None])
    local[:, lead + window:lead + window + n] = np.where(short_side, -drho, drho)
    spread = []
    if design.window is not None and not design.full_turn:
        bc = 2.0 * b * c
        for end, at_lo in ((0, True), (1, False)):
            holds, target, p = _span_extreme(a, d, phi, at_lo)
            slope = np.zeros((n_rows, n))
            slope[np.arange(n_rows), target] = np.where(holds, 0.0, 2.0 * a * d * np.sin(p) / bc)
            spread.append((lead + end, design.scale * (-slope if at_lo else slope)))
    if design.timing == "free":
        slope = np.zeros((n_rows, n))
        slope[:, 0] -= s * design.scale
        slope[:, n - 1] += s * design.scale
        spread.append((violated.shape[1] - 1, slope))
    scale = weight / design.scale
    local = np.nan_to_num(np.where(violated, local, 0.0) * scale)
    spread = [(row, np.nan_to_num(np.where(violated[:, row:row + 1], slope, 0.0) * scale)) for row, slope in spread]
    return local, spread
