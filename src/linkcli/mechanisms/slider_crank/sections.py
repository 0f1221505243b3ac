"""The slider-crank's own report sections (docs/format.md, the slider-crank): linkage,
grashof (its class), transmission, motion and kinematics rows, from the closed forms of
`kinematics` (dead centres, stroke, time ratio, velocities and accelerations, Norton ch. 6-7).
Angles leave in the file's angle unit, lengths in its length unit.

Transmission angle mu = arccos(|e - a sin(phi)| / b) falls as |h| = |e - a sin(phi)| grows,
so its extremes over an arc are at the arc's ends, at phi = +-90 deg (|h| largest) or where
a sin(phi) = e (mu = 90 deg). Ties within 1e-9 go to the first angle counter-clockwise from
0 (full turn) or from the arc's start (rocking crank).
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.mechanisms.columns import TRANSMISSION_BAND, rows_of
from linkcli.mechanisms.columns import angle_out as _ang
from linkcli.mechanisms.columns import turn_out as _dang
from linkcli.mechanisms.protocol import Study
from linkcli.mechanisms.slider_crank import kinematics as sc
from linkcli.noise import first_max, first_min, snap, snap_series
from linkcli.textnum import num


def size(sl) -> float:
    """The slider-crank's scale: round-off below NOISE_FLOOR times it is 0."""
    return max(sl.input, sl.coupler, abs(sl.offset))


def study_arc(sl, near=None) -> Study | None:
    """The crank's study: a full turn, or the arc (lo, hi) with hi >= lo (rad, running lo ->
    hi counter-clockwise) holding `near`; None when it never assembles."""
    arcs = sc.input_arcs(*sl.abe)
    if arcs is None:
        return Study(True, (0.0, sc.TWO_PI))
    if not arcs:
        return None
    lo, hi = sc.choose_arc(arcs, near)
    return Study(False, (lo, lo + sc.arc_sweep(lo, hi)))


def linkage_section(sl, u) -> dict:
    out = {"mechanism": "slider-crank", "input": sl.input, "coupler": sl.coupler,
           "offset": snap(float(sl.offset), size(sl)), "branch": sl.branch}
    if sl.coupler_point is not None:
        out["coupler_point"] = [snap(float(v), size(sl)) for v in sl.coupler_point]
    return out


def grashof_section(sl) -> dict:
    """class (slider-crank, rocking-slider; change-point within 1e-9 of a + |e| = b, where
    the rod stands normal to the guide and the branches meet), with the two sides of the
    test a + |e| <= b."""
    return sc.classify(*sl.abe)


def transmission_extremes(sl, full: bool, arc):
    """(mu_min, phi_at_min, mu_max, phi_at_max) over the crank's range (module docstring)."""
    a, b, e = sl.abe
    lo, hi = arc
    cands = [math.pi / 2, -math.pi / 2]
    if abs(e) <= a:
        root = math.asin(e / a)
        cands += [root, math.pi - root]
    if full:
        phi = np.sort(np.mod(np.array(cands), sc.TWO_PI))  # sweep order from 0
    else:
        inside = [c for c in cands if bool(sc.arc_contains((lo, hi), c))]
        phi = np.array([lo] + sorted(inside, key=lambda c: (c - lo) % sc.TWO_PI) + [hi])
    p = sc.pose(a, b, e, phi, "open")  # mu does not depend on the branch
    mu = np.where(p.valid, p.mu, np.nan)
    mu = np.where(np.isnan(mu), np.inf, mu)
    i = int(first_min(mu))
    mu_hi = np.where(np.isinf(mu), -np.inf, mu)
    j = int(first_max(mu_hi))
    return float(mu[i]), float(phi[i]), float(mu_hi[j]), float(phi[j])


def transmission_section(sl, study: Study, u, notes: list) -> dict:
    """Extremes over the crank's range; a note when mu falls below the recommended band."""
    mn, at_mn, mx, at_mx = transmission_extremes(sl, study.full_turn, study.arc)
    band = TRANSMISSION_BAND[0]
    if math.degrees(mn) < band * (1 - 1e-9):
        notes.append(f"transmission angle falls below the recommended {band:g} deg "
                     f"({num(math.degrees(mn))}..{num(math.degrees(mx))} deg over the crank's range)")
    return {"min": _dang(u, mn), "max": _dang(u, mx),
            "input_at_min": _ang(u, at_mn), "input_at_max": _ang(u, at_mx)}


def motion_section(sl, study: Study, u) -> dict:
    """input_full_turn, input_range (rocking crank), slider_range, stroke, and for a turning
    crank time_ratio (advance over return, >= 1) and slow_stroke (outward: folded ->
    extended dead centre; return; neither)."""
    full, arc = study.full_turn, study.arc
    m = sc.motion(*sl.abe, sl.branch, near=None if full else arc[0])
    out = {"input_full_turn": full}
    if not full:
        out["input_range"] = [_ang(u, arc[0]), _ang(u, arc[1])]
    lo, hi = m["slider_range"]
    scale = size(sl)
    out["slider_range"] = [snap(lo, scale), snap(hi, scale)]
    out["stroke"] = snap(m["stroke"], scale)
    if full:
        out["time_ratio"] = m["time_ratio"]
        out["slow_stroke"] = m["slow_stroke"]
    return out


def kinematics_rows(sl, study: Study, speed, steps, u) -> list[dict]:
    """One row per step (protocol.Study.rows): input, coupler (rod
    angle), slider, transmission, coupler_velocity, slider_velocity, coupler_acceleration,
    slider_acceleration (angle unit per s, per s^2; length unit per s, per s^2), and the
    coupler point's position, velocity and acceleration when given."""
    a, b, e = sl.abe
    phi, shown = study.rows(steps)
    p = sc.pose(a, b, e, phi, sl.branch)
    vs, w3 = sc.velocities(a, b, p, speed)
    acc, a3 = sc.accelerations(a, b, p, speed)
    rate, rate2 = abs(speed), speed * speed
    scale = size(sl)
    cols = [("input", u.from_rad(shown)), ("coupler", u.from_rad(snap(sc.wrap(p.theta), 1.0))),
            ("slider", snap_series(p.slider, scale)), ("transmission", u.from_rad(p.mu)),
            ("coupler_velocity", u.from_rad(snap_series(w3, rate))),
            ("slider_velocity", snap_series(vs, scale * rate)),
            ("coupler_acceleration", u.from_rad(snap_series(a3, rate2))),
            ("slider_acceleration", snap_series(acc, scale * rate2))]
    if sl.coupler_point is not None:
        px, py = sl.coupler_point
        x, y = sc.coupler_point(a, p, px, py)
        (vx, vy), (ax, ay) = sc.coupler_point_motion(a, b, p, px, py, speed)
        big = scale + math.hypot(px, py)
        cols += [("coupler_point_x", snap_series(x, big)), ("coupler_point_y", snap_series(y, big)),
                 ("coupler_point_vx", snap_series(vx, big * rate)),
                 ("coupler_point_vy", snap_series(vy, big * rate)),
                 ("coupler_point_ax", snap_series(ax, big * rate2)),
                 ("coupler_point_ay", snap_series(ay, big * rate2))]
    return rows_of(cols, p.valid)
