"""The offset slider-crank, vectorized over angles and over populations (numpy only).

Conventions (docs/format.md, slider-crank): crank `input` a pivoted at A0 =
origin, connecting rod `coupler` b, signed `offset` e; the slider axis is parallel to x at
y = e, and the slider position s is the x coordinate of the slider pin B = (s, e). The loop

    a e^{i phi} + b e^{i theta} = s + i e

gives, with h = e - a sin(phi) (the rise from A to B) and w = b cos(theta),

    b sin(theta) = h,   w = sigma sqrt(b^2 - h^2),   s = a cos(phi) + w,

sigma = +1 on the `open` branch (B ahead of A along +x), -1 on the `crossed` branch.
The transmission angle (between the rod and the guide's normal; 90 deg ideal) is
mu = arccos(|h| / b), evaluated as
atan2(sqrt(b^2 - h^2), |h|) so that it keeps full precision near 0 and 90 deg.

Derivatives at crank speed w2 and crank acceleration alpha2 (differentiate b sin(theta) = h
and s = a cos(phi) + b cos(theta); Norton, Design of Machinery, ch. 6-7, slider-crank):

    w3     = -a w2 cos(phi) / w
    s'     = -a w2 sin(phi) - h w3
    alpha3 = (a w2^2 sin(phi) - a alpha2 cos(phi) + h w3^2) / w
    s''    = -a alpha2 sin(phi) - a w2^2 cos(phi) - h alpha3 - w w3^2

They are infinite where the rod is normal to the guide (w = 0: a limit position).

Every function broadcasts: lengths of shape (N, 1) against angles of shape (M,) give (N, M).
Nothing here warns (np.errstate); a pose that does not assemble is NaN.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkcli.angles import wrap  # the one wrap: angles in (-pi, pi]
from linkcli.mechanisms.slider_crank.model import SliderCrank  # noqa: F401  (re-exported: the dataclass lives with FourBar, no numpy)

TWO_PI = 2.0 * math.pi
BRANCHES = ("open", "crossed")
ASSEMBLY_SLACK = 1e-12  # relative: b^2 - h^2 down to -slack b^2 still assembles (w = 0)
LIMIT_RTOL = 1e-9  # |w| <= this * b: the rod is normal to the guide (velocities infinite)
CHANGE_POINT_RTOL = 1e-9  # |a + |e| - b| <= this * b: the class boundary (change point)
SLIDER_CLASSES = ("slider-crank", "rocking-slider", "change-point", "no-assembly")


def root_sign(branch):
    """sigma: +1 open (B ahead of A along +x), -1 crossed; or an array of signs as given."""
    if isinstance(branch, str):
        if branch not in BRANCHES:
            raise ValueError(f"branch must be one of {BRANCHES}, got {branch!r}")
        return 1.0 if branch == "open" else -1.0
    return np.asarray(branch, dtype=float)


# ---------------------------------------------------------------- position

def slider_from_trig(crank, rod, offset, cos_phi, sin_phi, branch="open"):
    """(s, h, w, valid) from precomputed cos(phi), sin(phi): s = a cos(phi) + w,
    w = sigma sqrt((b - h)(b + h)), h = e - a sin(phi). Only correctly rounded operations,
    so equal inputs give equal bits whatever the array shape. s is NaN where |h| > b."""
    a, b, e = (np.asarray(v, dtype=float) for v in (crank, rod, offset))
    with np.errstate(invalid="ignore", over="ignore"):
        h = e - a * sin_phi
        disc = (b - h) * (b + h)
        valid = disc >= -ASSEMBLY_SLACK * b * b
        w = root_sign(branch) * np.sqrt(np.where(valid, np.maximum(disc, 0.0), np.nan))
        s = a * cos_phi + w
    return s, h, w, valid


@dataclass
class SliderPose:
    """The slider-crank at crank angles phi; every array has the broadcast shape, NaN where
    it does not assemble."""

    phi: np.ndarray
    slider: np.ndarray  # s, x of the slider pin B
    theta: np.ndarray  # rod angle, direction A -> B
    mu: np.ndarray  # transmission angle, [0, pi/2]
    rise: np.ndarray  # h = e - a sin(phi) = b sin(theta)
    run: np.ndarray  # w = s - a cos(phi) = b cos(theta)
    valid: np.ndarray  # bool


def pose(crank, rod, offset, phi, branch="open") -> SliderPose:
    """Closure of a e^{i phi} + b e^{i theta} = s + i e on a branch (module docstring)."""
    phi = np.asarray(phi, dtype=float)
    c, s_ = np.cos(phi), np.sin(phi)
    s, h, w, valid = slider_from_trig(crank, rod, offset, c, s_, branch)
    with np.errstate(invalid="ignore"):
        theta = np.arctan2(h, w)
        mu = np.arctan2(np.abs(w), np.abs(h))
    shape = s.shape
    return SliderPose(phi=np.broadcast_to(phi, shape), slider=s, theta=theta, mu=mu,
                      rise=np.broadcast_to(h, shape), run=w, valid=np.broadcast_to(valid, shape))


def pin_b(offset, p: SliderPose):
    """(x, y) of the slider pin B = (s, e), broadcast; NaN where it does not assemble."""
    y = np.where(p.valid, np.asarray(offset, dtype=float), np.nan)
    return p.slider, np.broadcast_to(y, p.slider.shape)


def pin_a(crank, phi):
    """(x, y) of the crank pin A = a e^{i phi}."""
    return crank * np.cos(phi), crank * np.sin(phi)


# ---------------------------------------------------------------- velocity, acceleration

def _limit(rod, p: SliderPose):
    return np.abs(p.run) <= LIMIT_RTOL * np.asarray(rod, dtype=float)


def velocities(crank, rod, p: SliderPose, w2):
    """(slider velocity s', rod angular velocity w3) at crank speed w2 (rad/s):
    w3 = -a w2 cos(phi) / w, s' = -a w2 sin(phi) - h w3. Infinite at a limit position
    (rod normal to the guide), NaN where the pose does not assemble."""
    a = np.asarray(crank, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        w3 = -a * w2 * np.cos(p.phi) / p.run
        vs = -a * w2 * np.sin(p.phi) - p.rise * w3
    lim = _limit(rod, p) & p.valid
    return np.where(lim, np.inf, vs), np.where(lim, np.inf, w3)


def accelerations(crank, rod, p: SliderPose, w2, alpha2=0.0):
    """(slider acceleration s'', rod angular acceleration alpha3) at crank speed w2 and
    crank acceleration alpha2: alpha3 = (a w2^2 sin(phi) - a alpha2 cos(phi) + h w3^2) / w,
    s'' = -a alpha2 sin(phi) - a w2^2 cos(phi) - h alpha3 - w w3^2."""
    a = np.asarray(crank, dtype=float)
    cp, sp = np.cos(p.phi), np.sin(p.phi)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        w3 = -a * w2 * cp / p.run
        a3 = (a * w2 * w2 * sp - a * alpha2 * cp + p.rise * w3 * w3) / p.run
        acc = -a * alpha2 * sp - a * w2 * w2 * cp - p.rise * a3 - p.run * w3 * w3
    lim = _limit(rod, p) & p.valid
    return np.where(lim, np.inf, acc), np.where(lim, np.inf, a3)


def slider_partials(crank, rod, offset, phi, branch="open"):
    """(ds/da, ds/db, ds/de) at fixed phi: cos(phi) + h sin(phi) / w, b / w, -h / w
    (differentiate s = a cos(phi) + sigma sqrt(b^2 - h^2), h = e - a sin(phi)).
    Infinite at a limit position, NaN where it does not assemble."""
    p = pose(crank, rod, offset, phi, branch)
    b = np.asarray(rod, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        da = np.cos(p.phi) + p.rise * np.sin(p.phi) / p.run
        db = b / p.run
        de = -p.rise / p.run
    lim = _limit(rod, p) & p.valid
    return tuple(np.where(lim, np.inf, x) for x in (da, db, de))


# ---------------------------------------------------------------- coupler point

def coupler_point(crank, p: SliderPose, px, py):
    """P = A + (px + i py) e^{i theta}: coupler frame origin A, x along A -> B."""
    ax, ay = crank * np.cos(p.phi), crank * np.sin(p.phi)
    ct, st = np.cos(p.theta), np.sin(p.theta)
    return ax + px * ct - py * st, ay + px * st + py * ct


def coupler_point_motion(crank, rod, p: SliderPose, px, py, w2, alpha2=0.0):
    """((vx, vy), (ax, ay)) of the coupler point at crank speed w2, acceleration alpha2:
    P' = i a w2 e^{i phi} + i w3 q,  P'' = a (i alpha2 - w2^2) e^{i phi} + (i alpha3 - w3^2) q,
    q = (px + i py) e^{i theta}."""
    _, w3 = velocities(crank, rod, p, w2)
    _, a3 = accelerations(crank, rod, p, w2, alpha2)
    a = np.asarray(crank, dtype=float)
    cp, sp = np.cos(p.phi), np.sin(p.phi)
    ct, st = np.cos(p.theta), np.sin(p.theta)
    qx, qy = px * ct - py * st, px * st + py * ct
    with np.errstate(invalid="ignore", over="ignore"):
        vx = -a * w2 * sp - w3 * qy
        vy = a * w2 * cp + w3 * qx
        ax = -a * alpha2 * sp - a * w2 * w2 * cp - a3 * qy - w3 * w3 * qx
        ay = a * alpha2 * cp - a * w2 * w2 * sp + a3 * qx - w3 * w3 * qy
    return (vx, vy), (ax, ay)


# ---------------------------------------------------------------- class, range of motion

def class_code(crank, rod, offset):
    """Index into SLIDER_CLASSES, vectorized: the crank turns fully iff a + |e| <= b;
    within CHANGE_POINT_RTOL * b of equality a change point (the branches meet where the rod
    stands normal to the guide); |e| > a + b never assembles."""
    a, b, e = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (crank, rod, offset)))
    reach = a + np.abs(e)
    change = np.abs(reach - b) <= CHANGE_POINT_RTOL * b
    code = np.where(reach < b, 0, np.where(np.abs(e) > a + b, 3, 1))
    return np.where(change, 2, code)


def classify(crank, rod, offset) -> dict:
    """The class of one slider-crank with the figures that decide it (`grashof` section)."""
    return {"class": SLIDER_CLASSES[int(class_code(crank, rod, offset))],
            "crank_plus_offset": float(crank) + abs(float(offset)), "coupler": float(rod)}


def _asin_ratio(num, den_minus, den_plus):
    """asin(num / a) given (a - num)(a + num) = den_minus * den_plus, by atan2 (full
    precision near +-90 deg)."""
    return math.atan2(num, math.sqrt(max(den_minus * den_plus, 0.0)))


def input_arcs(crank, rod, offset):
    """Reachable crank angles: None for a full turn, [] if it never assembles, else a list
    of arcs (lo, hi), each running counter-clockwise from lo to hi, both in (-pi, pi]
    (hi < lo when the arc passes 180 deg; its sweep is arc_sweep(lo, hi)).

    It assembles where |h| <= b, i.e. sin(phi) in [(e - b)/a, (e + b)/a]; the limits are
    phi = asin((e -+ b)/a), written with atan2 and (a - q)(a + q) products."""
    a, b, e = float(crank), float(rod), float(offset)
    code = int(class_code(a, b, e))
    if code in (0, 2):
        return None
    if code == 3:
        return []
    lower_in = e - b > -a  # sin(phi) >= (e - b)/a cuts the circle
    upper_in = e + b < a  # sin(phi) <= (e + b)/a cuts the circle
    lo_l = _asin_ratio(e - b, a - e + b, a + e - b) if lower_in else None
    hi_u = _asin_ratio(e + b, a - e - b, a + e + b) if upper_in else None
    w = lambda x: float(wrap(x))  # noqa: E731
    if lower_in and not upper_in:
        return [(lo_l, w(math.pi - lo_l))]
    if upper_in and not lower_in:
        return [(w(math.pi - hi_u), hi_u)]
    return [(lo_l, hi_u), (w(math.pi - hi_u), w(math.pi - lo_l))]


def arc_sweep(lo, hi) -> float:
    """Counter-clockwise angle from lo to hi, in [0, 2 pi)."""
    return float(np.mod(hi - lo, TWO_PI))


def arc_contains(arc, phi, slack=1e-12):
    """Whether phi lies on the arc lo -> hi (ccw), widened by `slack` rad at both ends."""
    lo, hi = arc
    return np.mod(np.asarray(phi, dtype=float) - lo + slack, TWO_PI) <= arc_sweep(lo, hi) + 2 * slack


def choose_arc(arcs, near=None):
    """The arc holding angle `near` (default: the first)."""
    if near is not None:
        for arc in arcs:
            if bool(arc_contains(arc, near)):
                return arc
    return arcs[0]


def travels(crank, rod, offset, phi, sweep) -> bool:
    """Can the crank move from phi[0] to phi[-1] (sweep = their signed difference, its sign
    the direction) through every phi inside one assembling arc, without a limit position
    (where the slider-crank would change branch)? A turning crank always can."""
    arcs = input_arcs(crank, rod, offset)
    if arcs is None:
        return True
    if not arcs:
        return False
    phi = np.asarray(phi, dtype=float)
    lo, hi = choose_arc(arcs, phi[0])
    inside = np.mod(phi - lo, TWO_PI) <= arc_sweep(lo, hi) + 1e-9
    first, last = np.mod(phi[0] - lo, TWO_PI), np.mod(phi[-1] - lo, TWO_PI)
    return bool(np.all(inside)) and ((sweep >= 0 and last >= first) or (sweep < 0 and last <= first))


# ---------------------------------------------------------------- dead centres, stroke, time ratio

def dead_centres(crank, rod, offset, branch="open") -> dict:
    """Crank and rod collinear (ds/dphi = 0), vectorized; NaN where absent.

    extended: |A0 B| = a + b, s = sigma sqrt((a + b)^2 - e^2), phi = atan2(e, s);
    folded:   |A0 B| = |b - a|, s = sigma sgn(b - a) sqrt((b - a)^2 - e^2) (B on the
              branch), phi = atan2(-e, -s) when b > a (A behind A0), else atan2(e, s).
    Returns arrays extended_slider, extended_input, folded_slider, folded_input."""
    a, b, e = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (crank, rod, offset)))
    sig = root_sign(branch)
    with np.errstate(invalid="ignore"):
        r_ext = np.sqrt(np.where((a + b - np.abs(e)) >= 0, (a + b - e) * (a + b + e), np.nan))
        span = b - a
        near = np.abs(span) >= np.abs(e) - CHANGE_POINT_RTOL * b  # a change point keeps it
        r_fold = np.sqrt(np.where(near, np.maximum((span - e) * (span + e), 0.0), np.nan))
        s_ext = sig * r_ext
        direction = np.where(span >= 0, 1.0, -1.0)
        s_fold = sig * direction * r_fold
        phi_ext = np.arctan2(e, s_ext)
        phi_fold = np.arctan2(-direction * e, -direction * s_fold)  # A behind A0 when b > a
    nan = np.isnan
    return {"extended_slider": s_ext, "extended_input": np.where(nan(s_ext), np.nan, wrap(phi_ext)),
            "folded_slider": s_fold, "folded_input": np.where(nan(s_fold), np.nan, wrap(phi_fold))}


def stroke(crank, rod, offset):
    """Slider travel of a turning crank (NaN otherwise), vectorized:
    sqrt((a+b)^2 - e^2) - sqrt((b-a)^2 - e^2) = 4 a b / (sqrt((a+b)^2 - e^2) + sqrt((b-a)^2 - e^2)),
    the second form free of cancellation."""
    a, b, e, turns, r_ext, r_fold = _dead_centres(crank, rod, offset)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = 4.0 * a * b / (r_ext + r_fold)
    return np.where(turns, out, np.nan)


def _dead_centres(crank, rod, offset):
    """(a, b, e broadcast, whether the crank turns fully, R_ext, R_fold): the slider's
    distances from the crank pivot along the guide at the extended and folded dead
    centres, R = sqrt(L^2 - e^2) with L = a + b and b - a (NaN where the crank does not turn)."""
    a, b, e = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (crank, rod, offset)))
    code = class_code(a, b, e)
    with np.errstate(invalid="ignore"):
        r_ext = np.sqrt((a + b - e) * (a + b + e))
        r_fold = np.sqrt(np.maximum((b - a - e) * (b - a + e), 0.0))
    return a, b, e, (code == 0) | (code == 2), r_ext, r_fold


def time_ratio(crank, rod, offset, branch="open"):
    """(K, slow) for a crank turning counter-clockwise at constant speed, vectorized.

    The outward stroke (folded -> extended dead centre, |s| growing) takes the crank angle
    pi - sigma delta, the return pi + sigma delta, delta = atan2(e, R_fold) - atan2(e, R_ext)
    (R = sqrt(L^2 - e^2), L = b - a and a + b); K = (pi + |delta|) / (pi - |delta|) >= 1.
    slow: +1 the return stroke is slower, -1 the outward one, 0 equal (e = 0: K = 1 exactly).
    NaN (and 0) when the crank does not turn fully."""
    a, b, e, turns, r_ext, r_fold = _dead_centres(crank, rod, offset)
    with np.errstate(invalid="ignore", divide="ignore"):
        delta = np.arctan2(e, r_fold) - np.arctan2(e, r_ext)
        k = (math.pi + np.abs(delta)) / (math.pi - np.abs(delta))
    slow = np.sign(root_sign(branch) * delta)
    return np.where(turns, k, np.nan), np.where(turns, slow, 0.0)


SLOW_STROKE = {1.0: "return", -1.0: "outward", 0.0: "neither"}


def motion(crank, rod, offset, branch="open", near=None) -> dict:
    """Range of motion of one slider-crank on a branch: the crank arc (full turn or the arc
    holding `near`), slider_range (s_min, s_max), stroke, dead centres on the arc, and for a
    turning crank the time ratio with its slow stroke.

    s is extreme only at the arc ends and where crank and rod are collinear, so the range
    is exact from those candidates (no sampling)."""
    a, b, e = float(crank), float(rod), float(offset)
    arcs = input_arcs(a, b, e)
    if arcs == []:
        return {"assembles": False}
    full = arcs is None
    lo, hi = (-math.pi, math.pi) if full else choose_arc(arcs, near)
    dc = {k: float(v) for k, v in dead_centres(a, b, e, branch).items()}
    out = {"assembles": True, "input_full_turn": full,
           "input_arc": None if full else (lo, hi)}
    cands = [] if full else [lo, hi]
    centres = {}
    for name in ("extended", "folded"):
        phi = dc[f"{name}_input"]
        if math.isfinite(phi) and (full or bool(arc_contains((lo, hi), phi, 1e-9))):
            centres[name] = {"input": phi, "slider": dc[f"{name}_slider"]}
            cands.append(phi)
    vals = [float(v) for v in pose(a, b, e, np.array(cands), branch).slider if math.isfinite(v)]
    vals += [c["slider"] for c in centres.values()]  # the closed form, exact at the extremes
    s_lo, s_hi = min(vals), max(vals)
    out["dead_centres"] = centres
    out["slider_range"] = (s_lo, s_hi)
    out["stroke"] = float(stroke(a, b, e)) if full else s_hi - s_lo
    if full:
        k, slow = time_ratio(a, b, e, branch)
        out["time_ratio"] = float(k)
        out["slow_stroke"] = SLOW_STROKE[float(slow)]
    return out
