"""Precision-position synthesis of an offset slider-crank: pairs (phi_i, s_i) -> a, b, e.

Derivation. The pin B = (s, e) lies at rod length b from the crank pin A = a e^{i phi}:

    (s - a cos(phi))^2 + (e - a sin(phi))^2 = b^2
    s^2 - 2 a s cos(phi) + a^2 - 2 a e sin(phi) + e^2 = b^2
    2 a s cos(phi) + 2 a e sin(phi) - (a^2 + e^2 - b^2) = s^2,

linear in x1 = 2a, x2 = 2ae, x3 = a^2 + e^2 - b^2 (rows [s_i cos(phi_i), sin(phi_i), -1],
right-hand side s_i^2): a = x1 / 2, e = x2 / x1, b^2 = a^2 + e^2 - x3. Three pairs give the
exact slider-crank (on either branch: the equation holds for both roots); a Gauss-Newton
polish on the true slider error of the chosen branch then removes the round-off of the
linear solve. A negative x1 means the crank points the other way: a e^{i phi} =
|a| e^{i (phi + pi)}, so the length is reported positive and the crank angles as phi + 180.

More pairs: the linear least-squares solution and the exact solutions of up to
SUBSET_STARTS three-pair subsets are starts, on both branches, for a damped Gauss-Newton
(Levenberg-Marquardt, Marquardt's column scaling, QR of the augmented Jacobian) on the true
error sum (s(phi_i) - s_i)^2, run to machine precision. The fit reported is the one that
assembles everywhere, then travels from the first to the last position without a limit
position (branch change), then the smallest sum (ties: the earlier start). numpy only.

Impossible data raise SchemaError naming the positions (1-based): coincident input angles,
a singular system, a zero or infinite crank, no real rod (b^2 <= 0); the last four are
decided by slider_system.slider_position_problem, which `linkcli check` runs as well.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkcli.errors import SchemaError
from linkcli.mechanisms.slider_crank.kinematics import SliderCrank, slider_from_trig, travels, wrap
from linkcli.types.precision_position.slider_system import ZERO_CRANK, slider_position_problem, subset_combinations

COINCIDENT = 1e-9  # rad: two crank angles closer than this are one position
MAX_ITER = 300
LAMBDA0 = 1e-3
LAMBDA_MAX = 1e16  # damping this large: no step lowers the sum any more (round-off)
STEP_RTOL = 4 * 2.0**-52  # relative step that counts as converged
HELD_RTOL = 1e-9  # |w| within this times b: the position lies on both branches


@dataclass(frozen=True)
class SliderFit:
    """A synthesized slider-crank and how it meets the positions."""

    linkage: SliderCrank
    input_angles: np.ndarray  # physical crank angles (rad): phi_i, or phi_i + pi if reversed
    target: np.ndarray  # s_i
    achieved: np.ndarray  # s(phi_i) on linkage.branch (NaN where it does not assemble)
    error: np.ndarray  # achieved - target
    objective: float  # sum of error^2 (length^2)
    exact: bool  # three positions: solved exactly
    crank_reversed: bool  # x1 < 0: the crank sits at phi + 180
    held: dict  # branch -> tuple of 1-based positions that branch reaches (exact case)
    branch_defect: bool  # the positions need both branches
    travels: bool  # the crank moves first -> last without a limit position
    converged: bool
    iterations: int
    starts: int
    method: str
    notes: tuple[str, ...]


def _names(idx) -> str:
    return ", ".join(str(int(i) + 1) for i in idx)


def _error(expected: str, got: str, key: str, path, line) -> SchemaError:
    return SchemaError(expected, got, path=path, line=line, key=key)


def linear_system(phi, s):
    """Rows [s cos(phi), sin(phi), -1] and right-hand side s^2 (module docstring)."""
    phi, s = np.asarray(phi, dtype=float), np.asarray(s, dtype=float)
    m = np.stack([s * np.cos(phi), np.sin(phi), -np.ones_like(s)], axis=-1)
    return m, s * s


def lengths_of(x):
    """(a signed, b^2, e) from x = (2a, 2ae, a^2 + e^2 - b^2), vectorized over rows."""
    x = np.atleast_2d(x)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        a = x[:, 0] / 2.0
        e = x[:, 1] / x[:, 0]
        b2 = a * a + e * e - x[:, 2]
    return a, b2, e


def check_positions(phi, s, *, path=None, line=None) -> None:
    """Equal lengths, at least three, finite, distinct crank angles (SchemaError)."""
    phi, s = np.asarray(phi, dtype=float), np.asarray(s, dtype=float)
    if phi.shape != s.shape or phi.ndim != 1 or len(phi) < 3:
        raise _error("at least three (input angle, slider position) pairs",
                     f"{len(np.atleast_1d(phi))} angles and {len(np.atleast_1d(s))} slider positions",
                     "positions", path, line)
    bad = np.nonzero(~(np.isfinite(phi) & np.isfinite(s)))[0]
    if len(bad):
        raise _error("finite angles and slider positions", f"positions {_names(bad)} not finite",
                     "positions", path, line)
    diff = np.abs(wrap(phi[:, None] - phi[None, :]))
    i, j = np.nonzero(np.triu(diff < COINCIDENT, 1))
    if len(i):
        raise _error("distinct input angles (each position a different crank angle)",
                     f"positions {i[0] + 1} and {j[0] + 1} at the same angle",
                     "positions.input", path, line)


# ---------------------------------------------------------------- the damped Gauss-Newton

def _residuals(x, sign, cos_phi, sin_phi, s):
    a, b, e = x[:, 0:1], x[:, 1:2], x[:, 2:3]
    sl, h, w, valid = slider_from_trig(a, b, e, cos_phi, sin_phi, sign[:, None])
    r = sl - s
    with np.errstate(invalid="ignore", over="ignore"):
        cost = np.where(np.all(valid, axis=1), np.einsum("km,km->k", r, r), np.inf)
    return r, h, w, cost


def _jacobian(x, h, w, cos_phi, sin_phi):
    """ds/d(a, b, e) = (cos(phi) + h sin(phi) / w, b / w, -h / w), shape (K, n, 3)."""
    b = x[:, 1:2]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        jac = np.stack([cos_phi + h * sin_phi / w, b / w, -h / w], axis=-1)
    return np.where(np.isfinite(jac), jac, 0.0)


def refine(x0, sign, phi, s, max_iter=MAX_ITER):
    """Levenberg-Marquardt on sum (s(phi_i; a, b, e) - s_i)^2, batched over K starts.

    x0 (K, 3) starts (a, b, e), sign (K,) +1 open / -1 crossed. Each step solves
    [J; sqrt(lam) D] dx = [-r; 0] by QR (D: Marquardt's column norms); a step is kept only
    when every position still assembles and the sum falls. A start stops when its relative
    step falls to STEP_RTOL (converged) or no damping finds a lower sum (converged when the
    gradient is at round-off). Returns (x, cost, converged, iterations)."""
    x = np.array(x0, dtype=float)
    sign = np.asarray(sign, dtype=float)
    k = x.shape[0]
    cp, sp = np.cos(phi), np.sin(phi)
    r, h, w, cost = _residuals(x, sign, cp, sp, s)
    lam = np.full(k, LAMBDA0)
    done = ~np.isfinite(cost)
    converged = np.zeros(k, dtype=bool)
    iterations = 0
    eye = np.eye(3)
    while not np.all(done) and iterations < max_iter:
        iterations += 1
        act = np.nonzero(~done)[0]
        jac = _jacobian(x[act], h[act], w[act], cp, sp)
        col = np.sqrt(np.einsum("knj,knj->kj", jac, jac))
        col = np.where(col > 0, col, 1.0)
        aug = np.concatenate([jac, np.sqrt(lam[act])[:, None, None] * col[:, None, :] * eye], axis=1)
        rhs = np.concatenate([-r[act], np.zeros((len(act), 3))], axis=1)
        q, rr = np.linalg.qr(aug)
        qtb = np.einsum("kmj,km->kj", q, rhs)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            step = np.linalg.solve(rr, qtb[:, :, None])[:, :, 0]
        step = np.where(np.isfinite(step), step, 0.0)
        x_new = x[act] + step
        r_new, h_new, w_new, cost_new = _residuals(x_new, sign[act], cp, sp, s)
        better = cost_new < cost[act]
        idx = act[better]
        x[idx], r[idx], h[idx], w[idx], cost[idx] = (x_new[better], r_new[better], h_new[better],
                                                      w_new[better], cost_new[better])
        lam[idx] = np.maximum(lam[idx] * 0.2, 1e-300)
        lam[act[~better]] *= 10.0
        tiny = np.max(np.abs(step) / np.maximum(np.abs(x_new), 1e-300), axis=1) <= STEP_RTOL
        grad = np.abs(np.einsum("knj,kn->kj", jac, r[act])).max(axis=1)
        scale = np.sqrt(np.einsum("knj,knj->k", jac, jac) * cost[act]) + 1e-300
        stuck = (lam[act] > LAMBDA_MAX)
        finished = (better & tiny) | stuck | (cost[act] == 0.0)
        converged[act] |= (better & tiny) | (cost[act] == 0.0) | (stuck & (grad <= 1e-7 * scale))
        done[act] |= finished
    return x, cost, converged, iterations


# ---------------------------------------------------------------- synthesis

def _physical(a, b, e, phi):
    """Positive lengths and physical crank angles: a < 0 is the crank at phi + pi."""
    reversed_ = a < 0
    return abs(a), abs(b), e, (wrap(phi + math.pi) if reversed_ else np.asarray(phi, float)), reversed_


REVERSED_NOTE = ("linear solution 2a < 0: the crank points opposite to the input angle (it sits at "
                 "phi + 180); its length is reported positive and the crank angles turned by 180")
TRAVEL_NOTE = ("branch defect: the crank cannot move from the first to the last position without "
               "passing a limit position (the slider-crank would change branch)")


def synthesize(phi, s, *, path=None, line=None) -> SliderFit:
    """Slider-crank through positions (phi_i rad, s_i length): exact for three, least
    squares refined on the true slider error for more (module docstring)."""
    phi, s = np.asarray(phi, dtype=float), np.asarray(s, dtype=float)
    check_positions(phi, s, path=path, line=line)
    refused = slider_position_problem(phi.tolist(), s.tolist())  # what `check` refuses too
    if refused is not None:
        raise _error(*refused, "positions", path, line)
    n = len(phi)
    scale = float(np.max(np.abs(s)))
    sn = s / scale  # the fit runs on lengths divided by the largest |s|: scale-free
    m, rhs = linear_system(phi, sn)
    x = np.linalg.lstsq(m, rhs, rcond=None)[0]
    a, b2, e = (float(v[0]) for v in lengths_of(x))
    if n == 3:  # b2 > 0: slider_position_problem refused the rest (round-off aside)
        fit = _exact(phi, sn, a, math.sqrt(max(b2, 0.0)), e)
    else:
        fit = _least_squares(phi, sn, a, b2, e, path, line)
    return _report(phi, s, scale, *fit)


def _exact(phi, sn, a, b, e):
    """Three positions: the branch holding most of them (ties: open), polished on it."""
    w = sn - a * np.cos(phi)
    held = {"open": tuple(i + 1 for i in range(3) if w[i] >= -HELD_RTOL * b),
            "crossed": tuple(i + 1 for i in range(3) if w[i] <= HELD_RTOL * b)}
    branch = "open" if len(held["open"]) >= len(held["crossed"]) else "crossed"
    x, sign = np.array([[a, b, e]]), np.array([1.0 if branch == "open" else -1.0])
    defect = len(held[branch]) < 3
    converged, iterations = True, 0
    if not defect:  # polish: the linear solve's round-off, not the fit, is removed here
        xr, cost, conv, iterations = refine(x, sign, phi, sn)
        if np.isfinite(cost[0]):
            x, converged = xr, bool(conv[0])
    return x[0], branch, True, held, defect, converged, iterations, 1, "linear-exact+gauss-newton"


def _subset_starts(phi, sn):
    idx = np.array(subset_combinations(len(phi)))
    m, rhs = linear_system(phi[idx], sn[idx])  # (C, 3, 3), (C, 3)
    ok = np.abs(np.linalg.det(m)) > 1e-12
    x = np.zeros((len(idx), 3))
    x[ok] = np.linalg.solve(m[ok], rhs[ok][:, :, None])[:, :, 0]
    a, b2, e = lengths_of(x)
    good = ok & np.isfinite(a) & np.isfinite(e) & (np.abs(a) > ZERO_CRANK) & (b2 > 0)
    return np.stack([a, np.sqrt(np.maximum(b2, 0.0)), e], axis=1)[good]


def _least_squares(phi, sn, a, b2, e, path, line):
    starts = [np.array([[a, math.sqrt(b2), e]])] if b2 > 0 else []
    starts.append(_subset_starts(phi, sn))
    x0 = np.concatenate(starts, axis=0)
    if not len(x0):
        raise _error("positions that a real rod can join",
                     f"positions {_names(range(len(phi)))} need coupler^2 = {b2:.6g} (scaled) <= 0, "
                     "and no three of them give a real rod", "positions", path, line)
    # a start must assemble everywhere: lengthen its rod to the largest rise needed
    h = x0[:, 2:3] - x0[:, 0:1] * np.sin(phi)[None, :]
    x0[:, 1] = np.maximum(x0[:, 1], np.max(np.abs(h), axis=1) * (1 + 1e-6))
    x0 = np.concatenate([x0, x0], axis=0)
    sign = np.concatenate([np.ones(len(x0) // 2), -np.ones(len(x0) // 2)])
    x, cost, conv, iterations = refine(x0, sign, phi, sn)
    order = np.argsort(cost, kind="stable")
    finite = [i for i in order if np.isfinite(cost[i])]
    sweep = float(phi[-1] - phi[0])
    chosen = finite[0] if finite else int(order[0])
    for i in finite:  # a few dozen candidates, once: the best one that travels
        aa, bb, ee, ph, _ = _physical(*x[i], phi)
        if travels(aa, bb, ee, ph, sweep):
            chosen = i
            break
    branch = "open" if sign[chosen] > 0 else "crossed"
    return (x[chosen], branch, False, {}, False, bool(conv[chosen]), iterations, len(x0),
            "linear-least-squares+levenberg-marquardt")


def _report(phi, s, scale, x, branch, exact, held, defect, converged, iterations, starts, method):
    a, b, e, phi_phys, reversed_ = _physical(*(float(v) for v in x), phi)
    a, b, e = a * scale, b * scale, e * scale
    linkage = SliderCrank(input=a, coupler=b, offset=e, branch=branch)
    sl, _, _, _ = slider_from_trig(a, b, e, np.cos(phi_phys), np.sin(phi_phys), branch)
    err = sl - s
    goes = travels(a, b, e, phi_phys, float(phi[-1] - phi[0]))
    notes = [REVERSED_NOTE] if reversed_ else []
    if defect:
        notes.append("branch defect: positions " + (", ".join(map(str, held["open"])) or "none")
                     + " lie on the open branch and " + (", ".join(map(str, held["crossed"])) or "none")
                     + f" on the crossed branch; reported on the {branch} branch")
    if not goes:
        notes.append(TRAVEL_NOTE)
    with np.errstate(invalid="ignore", over="ignore"):
        objective = float(err @ err) if np.all(np.isfinite(err)) else math.inf
    return SliderFit(linkage=linkage, input_angles=phi_phys, target=s, achieved=sl, error=err,
                     objective=objective, exact=exact, crank_reversed=bool(reversed_), held=held,
                     branch_defect=bool(defect), travels=goes, converged=converged,
                     iterations=int(iterations), starts=int(starts), method=method, notes=tuple(notes))
