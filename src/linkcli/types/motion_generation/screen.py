"""Defects and constraints of many candidate four-bars at once (numpy, vectorized over
candidates): the population form of `assemble.check_linkage`, plus the file's constraints.

A candidate is params (K, 10) in assemble.PARAM_NAMES order, its input angle at each pose
phi (K, n) in rad and its branch sign at each pose (K, n) (-1 open, +1 crossed).

* assembly: it does not assemble at a pose, or (exact synthesis) misses a pose by more
  than EXACT_RTOL of the poses' scale;
* branch (circuit) defect: the poses lie on different branches, or on different arcs of
  reachable input angles (mechanisms.four_bar.kinematics.input_arcs, written here for arrays: two
  arcs exist when |b - c| > |a - d| and b + c < a + d, one in the upper and one in the lower
  half plane of phi);
* order defect (3 poses or more): a crank does not reach them in cyclic order in one sense,
  a rocker not monotonically along its arc (Sandor & Erdman vol. 1 sec. 8; Balli & Chand 2002);
* grashof: not the class the file asks for; transmission: mu leaves the window over the
  working span (the input's travel from the first pose to the last) or, for a class whose
  input must turn fully (crank-rocker, double-crank), over the full turn, as path-generation;
* bounds: a length, the ground pivot A0 or the ground angle outside a bound the file gives,
  or a length or coordinate beyond the sizes any file accepts (io.bounds.MAX_LENGTH);
  branch_choice: not on the branch the file asks for.

`quality` is the worst transmission deviation from 90 deg over the working span (rad,
lower is better): the ranking of exact candidates.
"""

from __future__ import annotations

import numpy as np

from linkcli.io.bounds import MAX_LENGTH
from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.types.path_generation.model import FULL_TURN, rho2_extremes

from .assemble import body_poses, pose_errors
from .constraints import WINDOW_TOL

TWO_PI = kin.TWO_PI
EXACT_RTOL = 1e-7  # relative to the poses' scale: an exact candidate missing a pose by more is not exact
BOUND_RTOL = 1e-9  # relative: a value this far outside a bound is on it
DEFECTS = ("assembly", "branch", "order", "grashof", "transmission", "bounds", "branch_choice")


def _arc_end(r, near, far):
    """Input angle where rho = r: 2 atan2(sqrt((r - near)(r + near)), sqrt((far - r)(far + r)))
    (four_bar.input_arcs, half-angle form)."""
    n = np.maximum((r - near) * (r + near), 0.0)
    m = np.maximum((far - r) * (far + r), 0.0)
    return 2.0 * np.arctan2(np.sqrt(n), np.sqrt(m))


def _inside(phi, lo, width):
    return np.mod(phi - lo, TWO_PI) <= width + 1e-12


def arcs(params, phi):
    """(full (K,), arc_lo (K, n), arc_width (K, n), arc_index (K, n)): whether the input
    turns fully, and the arc of reachable input angles each pose lies on (index -1: none)."""
    a, b, c, d = (params[:, k, None] for k in (4, 5, 6, 3))
    big = np.maximum(np.maximum(a, b), np.maximum(c, d))
    a, b, c, d = a / big, b / big, c / big, d / big
    near, far, r_lo, r_hi = np.abs(a - d), a + d, np.abs(b - c), b + c
    full = (r_lo <= near) & (r_hi >= far)
    never = (r_lo > far) | (r_hi < near)
    through0 = ~full & ~never & (r_lo <= near)
    through_pi = ~full & ~never & ~through0 & (r_hi >= far)
    g_hi, g_lo = _arc_end(r_hi, near, far), _arc_end(r_lo, near, far)
    shape = np.broadcast_shapes(phi.shape, a.shape)
    lo = np.zeros(shape)
    width = np.full(shape, TWO_PI)
    index = np.where(never, -1, 0) + np.zeros(shape, int)
    lo = np.where(through0, -g_hi, lo)
    width = np.where(through0, 2 * g_hi, width)
    lo = np.where(through_pi, g_lo, lo)
    width = np.where(through_pi, TWO_PI - 2 * g_lo, width)
    two = ~full & ~never & ~through0 & ~through_pi
    upper = _inside(phi, g_lo, g_hi - g_lo)
    lower = _inside(phi, -g_hi, g_hi - g_lo)
    lo = np.where(two, np.where(upper, g_lo, -g_hi), lo)
    width = np.where(two, g_hi - g_lo, width)
    index = np.where(two, np.where(upper, 0, np.where(lower, 1, -1)), index)
    single = through0 | through_pi
    index = np.where(single & ~_inside(phi, lo, width), -1, index)
    return full[:, 0], lo, width, index


def travel(full, lo, phi):
    """(order_ok (K,), span_lo (K,), span_width (K,)): the poses reached in order and the
    input's travel from the first pose to the last (ccw from span_lo over span_width)."""
    n = phi.shape[1]
    ccw = np.mod(phi - phi[:, :1], TWO_PI)[:, 1:]
    cw = np.mod(phi[:, :1] - phi, TWO_PI)[:, 1:]
    if n >= 2:
        ccw_ok = np.all(np.diff(ccw, axis=1) > 0, axis=1) & (ccw[:, 0] > 0)
        cw_ok = np.all(np.diff(cw, axis=1) > 0, axis=1) & (cw[:, 0] > 0)
    else:
        ccw_ok = cw_ok = np.ones(len(phi), bool)
    if n == 2:  # two poses: the shorter way round
        ccw_ok, cw_ok = ccw[:, 0] <= np.pi, ccw[:, 0] > np.pi
    along = np.mod(phi - lo[:, :1], TWO_PI)  # position along the (first pose's) arc
    step = np.diff(along, axis=1)
    mono = np.all(step > 0, axis=1) | np.all(step < 0, axis=1) if n >= 2 else np.ones(len(phi), bool)
    order_ok = np.where(full, ccw_ok | cw_ok, mono)
    span_lo = np.where(full, np.where(ccw_ok, phi[:, 0], phi[:, -1]), lo[:, 0] + along.min(axis=1))
    width = np.where(full, np.where(ccw_ok, ccw[:, -1], cw[:, -1]), along.max(axis=1) - along.min(axis=1))
    return order_ok, span_lo, width


def screen(problem, poses, params, phi, signs, scale: float, exact: bool) -> dict:
    """Every defect (bool arrays (K,) named in DEFECTS), quality, working transmission
    (mu_min, mu_max over the working span), the span, achieved poses and their errors."""
    params = np.atleast_2d(np.asarray(params, float))
    phi = np.atleast_2d(np.asarray(phi, float))
    signs = np.broadcast_to(np.asarray(signs, float), phi.shape)
    achieved, valid = body_poses(params, phi, signs)
    pos, ang = pose_errors(poses, achieved)
    a, b, c, d = (params[:, k] for k in (4, 5, 6, 3))
    bad = {}
    bad["assembly"] = ~np.all(valid, axis=1)
    if exact:
        bad["assembly"] |= (np.max(pos, axis=1) > EXACT_RTOL * scale) | (np.max(np.abs(ang), axis=1) > EXACT_RTOL)
    full, lo, width, index = arcs(params, phi)
    bad["branch"] = (np.any(signs != signs[:, :1], axis=1) | np.any(index != index[:, :1], axis=1)
                     | np.any(index < 0, axis=1))
    order_ok, span_lo, span_width = travel(full, lo, phi)
    bad["order"] = ~bad["branch"] & ~order_ok if phi.shape[1] >= 3 else np.zeros(len(phi), bool)
    code = kin.grashof_code(a, b, c, d)
    bad["grashof"] = (code != kin.GRASHOF_CLASSES.index(problem.grashof)
                      if problem.grashof != "any" else np.zeros(len(phi), bool))
    r2_min, r2_max = rho2_extremes(a, d, span_lo, span_width)
    mu_min = kin.transmission_angle(b, c, np.sqrt(r2_min))
    mu_max = kin.transmission_angle(b, c, np.sqrt(r2_max))
    quality = np.maximum(np.pi / 2 - mu_min, mu_max - np.pi / 2)
    bad["transmission"] = np.zeros(len(phi), bool)
    if problem.transmission is not None:
        w_lo, w_hi = problem.transmission
        if problem.grashof in FULL_TURN:
            t_min = kin.transmission_angle(b, c, np.abs(a - d))
            t_max = kin.transmission_angle(b, c, a + d)
        else:
            t_min, t_max = mu_min, mu_max
        bad["transmission"] = (t_min < w_lo - WINDOW_TOL) | (t_max > w_hi + WINDOW_TOL)
    bad["bounds"] = out_of_bounds(problem, params)
    want = {"open": -1.0, "crossed": 1.0}.get(problem.branch)
    bad["branch_choice"] = (np.any(signs != want, axis=1) if want is not None
                            else np.zeros(len(phi), bool))
    count = np.sum([bad[k] for k in DEFECTS], axis=0)
    return {"defects": bad, "count": count, "quality": quality, "mu_min": mu_min, "mu_max": mu_max,
            "span": (span_lo, span_width), "achieved": achieved, "position_error": pos,
            "angle_error": ang, "full_turn": full}


def out_of_bounds(problem, params) -> np.ndarray:
    """(K,) True where a length, A0 or the ground angle is outside a bound the file gives,
    or a length or coordinate (A0, the body origin on the coupler) beyond the sizes any
    file accepts (MAX_LENGTH): a result must be read again by `analyze`."""
    out = np.any(np.abs(params[:, [0, 1, 3, 4, 5, 6, 7, 8]]) > MAX_LENGTH, axis=1)
    for k, name in ((3, "ground"), (4, "input"), (5, "coupler"), (6, "output")):
        r = problem.lengths.get(name)
        if r is not None:
            tol = BOUND_RTOL * max(r[1], 1e-300)
            out |= (params[:, k] < r[0] - tol) | (params[:, k] > r[1] + tol)
    if problem.ground_pivot is not None:
        for k, (lo, hi) in enumerate(problem.ground_pivot):
            tol = BOUND_RTOL * max(abs(lo), abs(hi), 1.0)
            out |= (params[:, k] < lo - tol) | (params[:, k] > hi + tol)
    if problem.ground_angle is not None:
        lo, hi = problem.ground_angle
        if hi - lo < TWO_PI * (1 - 1e-12):
            out |= np.mod(params[:, 2] - lo, TWO_PI) > (hi - lo) + 1e-12
    return out


def defect_names(result: dict, k: int) -> list[str]:
    """The defects of candidate k, by name."""
    return [name for name in DEFECTS if bool(result["defects"][name][k])]
