"""The four-bar's own report sections: linkage, grashof, transmission, motion, kinematics
(the conventions of docs/format.md), from the closed forms of `kinematics`.

Transmission extremes over a full turn or an arc are exact (kinematics.transmission_extremes:
rho is extreme only at phi = 0 and 180 deg); rows are the study's (protocol.Study.rows).
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.mechanisms.columns import TRANSMISSION_BAND, rows_of
from linkcli.mechanisms.columns import angle_out as _ang
from linkcli.mechanisms.columns import turn_out as _dang
from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.noise import snap, snap_series
from linkcli.textnum import num


def change_point_inputs(a, b, c, d) -> list[float]:
    """Input angles (rad, 0 and/or pi) where a change-point linkage (s + l = p + q, the
    conventions of docs/format.md) lies flat: A on the ground line, so rho = |a - d| (phi = 0) or a + d (phi =
    pi), and rho = |b - c| or b + c, all four links in line, within the change-point
    tolerance. There the open and crossed branches meet and the linkage may switch
    between them (Norton, Design of Machinery, sec. 2.13: the change-point hazard)."""
    if kin.GRASHOF_CLASSES[int(kin.grashof_code(a, b, c, d))] != "change-point":
        return []
    tol = kin.CHANGE_POINT_RTOL * max(a, b, c, d)
    return [phi for phi, rho in ((0.0, abs(a - d)), (math.pi, a + d))
            if min(abs(rho - abs(b - c)), abs(rho - (b + c))) <= tol]


def change_point_note(flat: list[float], fb, u) -> str:
    """The warning for a change-point linkage, naming the inputs where it lies flat."""
    where = " and ".join(num(_ang(u, phi)) for phi in flat)
    a, b, c, d = fb.abcd
    parallel = kin.same_lengths(a, c) and kin.same_lengths(b, d)
    switch = ("from parallelogram to antiparallelogram" if parallel
              else "between its open and crossed forms")
    return (f"change-point linkage: all four links lie in line at input {where} {u.angle}, where it can "
            f"switch {switch}; the {fb.branch} branch reported changes form there")



def linkage_section(fb, u) -> dict:
    out = {"ground": fb.ground, "input": fb.input, "coupler": fb.coupler, "output": fb.output,
           "branch": fb.branch}
    if fb.coupler_point is not None:
        size = max(fb.abcd)  # a coordinate that is round-off of 0 is 0
        out["coupler_point"] = [snap(float(v), size) for v in fb.coupler_point]
        out["ground_pivot"] = [snap(float(v), size) for v in fb.ground_pivot]
        out["ground_angle"] = _ang(u, fb.ground_angle)
        if fb.coupler_angle is not None:  # motion generation: the body's x axis from A -> B
            out["coupler_angle"] = _ang(u, fb.coupler_angle)
    return out


def transmission_section(fb, mot, span, u, notes) -> dict:
    a, b, c, d = fb.abcd
    lo, hi = mot.input_arc
    mn, at_mn, mx, at_mx = kin.transmission_extremes(a, b, c, d, lo, hi)
    out = {"min": _dang(u, mn), "max": _dang(u, mx),
           "input_at_min": _ang(u, at_mn), "input_at_max": _ang(u, at_mx)}
    if span is not None:
        start, sweep = span
        w_lo, w_hi = (start, start + sweep) if sweep >= 0 else (start + sweep, start)
        wmn, wat_mn, wmx, wat_mx = kin.transmission_extremes(a, b, c, d, w_lo, w_hi)
        out.update({"working_min": _dang(u, wmn), "working_max": _dang(u, wmx),
                    "working_input_at_min": _ang(u, wat_mn), "working_input_at_max": _ang(u, wat_mx)})
    band = TRANSMISSION_BAND
    if math.degrees(mn) < band[0] * (1 - 1e-9) or math.degrees(mx) > band[1] * (1 + 1e-9):  # round-off is inside
        notes.append(f"transmission angle leaves the recommended {band[0]:g}..{band[1]:g} deg band "
                     f"({num(math.degrees(mn))}..{num(math.degrees(mx))} deg over the input's range)")
    return out


def motion_section(mot, u) -> dict:
    out = {"input_full_turn": mot.input_full_turn}
    if not mot.input_full_turn:
        lo, hi = mot.input_arc
        out["input_range"] = [_ang(u, lo), _ang(u, hi)]
    out["output_full_turn"] = mot.output_full_turn
    if mot.output_range is not None:
        lo, hi = mot.output_range
        out["output_range"] = [_ang(u, lo), _ang(u, hi)]
    out["output_swing"] = _dang(u, mot.output_swing)
    if mot.time_ratio is not None:
        out["time_ratio"] = mot.time_ratio
    return out



def kinematics_rows(fb, study, speed, steps, u) -> list[dict]:
    """Rows at phi = k 360/steps for a full turn; at the centres of `steps` equal cells of
    a rocking input's arc (its ends are toggles, where a constant input speed would
    need infinite output speed): protocol.Study.rows."""
    a, b, c, d = fb.abcd
    phi, shown = study.rows(steps)
    p = kin.pose(a, b, c, d, phi, fb.branch)
    w3, w4 = kin.velocities(a, b, c, p, speed)
    a3, a4 = kin.accelerations(a, b, c, p, speed)
    rate, rate2 = abs(speed), speed * speed  # natural scales of the velocity and acceleration columns
    cols = [("input", u.from_rad(shown)), ("coupler", u.from_rad(snap(kin.wrap(p.theta), 1.0))),
            ("output", u.from_rad(snap(kin.wrap(p.psi), 1.0))), ("transmission", u.from_rad(p.mu)),
            ("coupler_velocity", u.from_rad(snap_series(w3, rate))),
            ("output_velocity", u.from_rad(snap_series(w4, rate))),
            ("coupler_acceleration", u.from_rad(snap_series(a3, rate2))),
            ("output_acceleration", u.from_rad(snap_series(a4, rate2)))]
    if fb.coupler_point is not None:
        cols += coupler_point_columns(fb, p, speed, w3, a3)
    return rows_of(cols, p.valid)  # where it cannot assemble (or A meets B0) only the input is known


def coupler_point_columns(fb, p, speed, w3, a3) -> list[tuple[str, np.ndarray]]:
    """The coupler point P over the motion, global frame (length unit, per s, per s^2).

    With r = R(theta) (px, py) the point's offset from A in the local frame:
        P = A0 + R(ground_angle) (a e^{i phi} + r),
        dP/dt = R(ground_angle) (a w2 i e^{i phi} + w3 i r),
        d2P/dt2 = R(ground_angle) (-a w2^2 e^{i phi} + alpha3 i r - w3^2 r)
    (constant input speed w2; rigid-body kinematics, Norton ch. 6-7)."""
    a = fb.input
    px, py = fb.coupler_point
    ct, st = np.cos(p.theta), np.sin(p.theta)
    rx, ry = px * ct - py * st, px * st + py * ct
    cp, sp = np.cos(p.phi), np.sin(p.phi)
    x, y = a * cp + rx, a * sp + ry
    vx, vy = -a * speed * sp - w3 * ry, a * speed * cp + w3 * rx
    ax = -a * speed * speed * cp - a3 * ry - w3 * w3 * rx
    ay = -a * speed * speed * sp + a3 * rx - w3 * w3 * ry
    cg, sg = math.cos(fb.ground_angle), math.sin(fb.ground_angle)
    gx, gy = fb.ground_pivot
    size = max(*fb.abcd, math.hypot(px, py))  # the linkage's scale: round-off below it is 0
    with np.errstate(invalid="ignore"):  # inf (a dead centre) times 0 stays undefined
        cols = [("coupler_point_x", gx + cg * x - sg * y), ("coupler_point_y", gy + sg * x + cg * y),
                ("coupler_point_vx", cg * vx - sg * vy), ("coupler_point_vy", sg * vx + cg * vy),
                ("coupler_point_ax", cg * ax - sg * ay), ("coupler_point_ay", sg * ax + cg * ay)]
    scales = (size + math.hypot(gx, gy),) * 2 + (size * abs(speed),) * 2 + (size * speed * speed,) * 2
    return [(name, snap_series(v, scale)) for (name, v), scale in zip(cols, scales)]

