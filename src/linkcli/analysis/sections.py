"""Problem + Solution -> report: an ordered dict of output-ready sections (docs/format.md, Output).

Angles leave here in the file's angle unit, wrapped to (-180, 180] deg where they are
positions; lengths in the file's length unit. Only the sections the problem asks for
(`meta.sections`) are computed. Rounding is the writers' job (export.py).
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.io.meta import ALL_SECTIONS
from linkcli.solution import MESSAGES, Solution
from linkcli.noise import NOISE_FLOOR, quantize, snap, snap_series
from linkcli.textnum import num

TRANSMISSION_BAND = (40.0, 140.0)  # deg: the usual recommendation (Norton, ch. 3)


def _ang(units, x):
    """A position angle in the output unit, wrapped to (-180, 180] deg; round-off of 0 (below
    the noise floor of 1 rad) is 0."""
    return float(units.from_rad(snap(float(kin.wrap(x)), 1.0)))


def _dang(units, x):
    """An angle difference or magnitude in the output unit (no wrap)."""
    return float(units.from_rad(float(x)))


def build(problem, solution: Solution) -> dict:
    """The report of one solved problem; degenerate data (a toggle, a flat linkage) gives
    inf or clipped values, never a RuntimeWarning on stderr."""
    with np.errstate(all="ignore"):
        return _build(problem, solution)


def _build(problem, solution: Solution) -> dict:
    meta = problem.meta
    u = meta.units
    want = set(meta.sections)
    rep: dict = {
        "file": meta.path,
        "title": meta.title,
        "type": meta.type,
        "status": solution.status.value,
        "message": solution.message or MESSAGES[solution.status],
        "units": {"length": u.length, "angle": u.angle},
    }
    notes = list(getattr(meta, "notes", ())) + list(solution.notes)
    fb = solution.linkage
    has_linkage = fb is not None
    mot = None
    slider = has_linkage and is_slider_crank(fb)
    if slider:
        _slider_sections(rep, problem, solution, fb, want, u, notes)
    if has_linkage and not slider and "lengths" in want:
        rep["linkage"] = linkage_section(fb, u)
    if has_linkage and not slider and "grashof" in want:
        rep["grashof"] = kin.grashof(*fb.abcd)
    if has_linkage and not slider and want & {"grashof", "transmission", "motion", "kinematics"}:
        flat = change_point_inputs(*fb.abcd)
        if flat:
            notes.append(change_point_note(flat, fb, u))
    if has_linkage and not slider and want & {"transmission", "motion", "kinematics"}:
        near = solution.working_span[0] if solution.working_span else None
        mot = kin.motion(*fb.abcd, fb.branch, near=near)
        if not mot.assembles:
            notes.append("the linkage cannot assemble at any input angle")
    if mot is not None and mot.assembles and "transmission" in want:
        rep["transmission"] = transmission_section(fb, mot, solution.working_span, u, notes)
    if mot is not None and mot.assembles and "motion" in want:
        rep["motion"] = motion_section(mot, u)
    if mot is not None and mot.assembles and "kinematics" in want:
        speed, steps = motion_study(problem, u)
        rep["kinematics"] = kinematics_rows(fb, mot, speed, steps, u)
        rep.setdefault("motion", {}).update(input_speed=_dang(u, speed), steps=steps)  # to reproduce it
    if has_linkage and "forces" in want and meta.loads is not None:
        from linkcli.analysis import forces
        study = forces.study_of(fb, mot, solution.working_span[0] if solution.working_span else None)
        if study is not None:
            rep.update(forces.echo(meta.loads))  # the load case as given: a result file round-trips
            speed, steps = motion_study(problem, u)
            rep["forces"] = forces.section(fb, study, speed, steps, meta.loads, u, notes)
        if "motion" in rep and study is not None:
            rep["motion"].update(input_speed=_dang(u, speed), steps=steps)
    if solution.positions is not None and "positions" in want:
        rep["positions"] = position_rows(solution.positions, u, linkage_scale(fb))
    if solution.positions is not None and "error" in want:
        rep["error"] = error_section(solution, u, meta.reference, linkage_scale(fb))
    for name, section in solution.sections.items():
        if name in want or name not in ALL_SECTIONS:
            rep[name] = section
    if "tolerance" in want and meta.tolerance is not None and has_linkage:
        from linkcli.analysis import tolerance
        rep["tolerance"] = tolerance.analyse(problem, solution)
    if "solver" in want and solution.solver is not None:
        rep["solver"] = solution.solver.report()
        if meta.reference is not None and solution.objective is not None:
            rep["solver"]["best_known"] = meta.reference.objective
            rep["solver"]["gap"] = rep.get("error", {}).get("gap", gap(solution.objective, meta.reference.objective))
    if notes:
        rep["notes"] = notes
    return rep


def is_slider_crank(linkage) -> bool:
    """The linkage is a linkcli.mechanisms.slider_crank.kinematics.SliderCrank (else a FourBar)."""
    from linkcli.analysis.forces import is_slider_crank as check
    return check(linkage)


def linkage_scale(linkage) -> float:
    """The linkage's size, the scale of its length errors (1 without a linkage)."""
    if linkage is None:
        return 1.0
    if is_slider_crank(linkage):
        from linkcli.analysis.slider_sections import size
        return size(linkage)
    return max(linkage.abcd)


def _slider_sections(rep, problem, solution, sl, want, u, notes) -> None:
    """linkage, grashof, transmission, motion and kinematics of a slider-crank
    (linkcli.analysis.slider_sections), in the four-bar's order and keys where they fit."""
    from linkcli.analysis import slider_sections as ss
    if "lengths" in want:
        rep["linkage"] = ss.linkage_section(sl, u)
    if "grashof" in want:
        rep["grashof"] = ss.grashof_section(sl)
        if rep["grashof"]["class"] == "change-point":
            notes.append("change-point slider-crank: input + |offset| = coupler (within 1e-9), the rod "
                         f"stands normal to the guide once a turn, where it can switch branch; the {sl.branch} "
                         "branch reported changes form there")
    if not want & {"transmission", "motion", "kinematics"}:
        return
    near = solution.working_span[0] if solution.working_span else None
    study = ss.study_arc(sl, near)
    if study is None:
        notes.append("the slider-crank cannot assemble at any crank angle")
        return
    full, arc = study
    if "transmission" in want:
        rep["transmission"] = ss.transmission_section(sl, full, arc, u)
        mn, _, mx, _ = ss.transmission_extremes(sl, full, arc)
        band = TRANSMISSION_BAND[0]
        if math.degrees(mn) < band * (1 - 1e-9):
            notes.append(f"transmission angle falls below the recommended {band:g} deg "
                         f"({num(math.degrees(mn))}..{num(math.degrees(mx))} deg over the crank's range)")
    if "motion" in want:
        rep["motion"] = ss.motion_section(sl, full, arc, u)
    if "kinematics" in want:
        speed, steps = motion_study(problem, u)
        rep["kinematics"] = ss.kinematics_rows(sl, full, arc, speed, steps, u, study_inputs)
        rep.setdefault("motion", {}).update(input_speed=_dang(u, speed), steps=steps)


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


def gap(value: float, best: float) -> float:
    """Relative gap to the best known value: (value - best) / |best| (absolute if best = 0),
    to whole multiples of the noise floor (its digits below are round-off)."""
    return quantize((value - best) / abs(best) if best != 0 else value - best)


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


def study_inputs(full_turn: bool, arc, steps: int):
    """(phi, shown): the input angles (rad) of the motion study's rows and as printed. A full
    turn: phi = k 2 pi / steps from 0, shown 0 .. 360 deg (docs/format.md); a rocking input over the arc
    (lo, hi): the centres of `steps` equal cells (its ends are toggles), shown wrapped. The
    kinematics and the forces sections share these rows."""
    if full_turn:
        phi = np.arange(steps) * (kin.TWO_PI / steps)
        return phi, phi
    lo, hi = arc
    phi = lo + (np.arange(steps) + 0.5) * ((hi - lo) / steps)
    return phi, kin.wrap(phi)


def motion_study(problem, u) -> tuple[float, int]:
    """(input speed in rad/s, steps) of the motion study: the problem's [motion], else 1 angle
    unit per second and 360 steps (types without [motion])."""
    return getattr(problem, "input_speed", None) or u.to_rad(1.0), getattr(problem, "steps", 360)


def kinematics_rows(fb, mot, speed, steps, u) -> list[dict]:
    """Rows at phi = k 360/steps for a full turn; at the centres of `steps` equal cells of
    a rocking input's arc (its ends are toggles, where a constant input speed would
    need infinite output speed)."""
    a, b, c, d = fb.abcd
    phi, shown = study_inputs(mot.input_full_turn, mot.input_arc, steps)
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
    rows = []
    for k in range(len(phi)):
        ok = bool(p.valid[k])  # where it cannot assemble (or A meets B0) only the input is known
        rows.append({name: (float(v[k]) if math.isfinite(v[k]) and (ok or name == "input") else None)
                     for name, v in cols})
    return rows


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


def error_scale(pos, length_scale: float) -> float:
    """The scale of a position error: 1 rad for angles, the linkage's size for distances."""
    return 1.0 if pos.kind == "angle" else length_scale


def position_rows(pos, u, length_scale: float) -> list[dict]:
    """One row per target; an error below the noise floor of its scale is 0."""
    err = snap(np.asarray(pos.error, dtype=float), error_scale(pos, length_scale))
    rows = []
    for k in range(len(pos.input)):
        if pos.kind == "angle":
            rows.append({"input": _ang(u, pos.input[k]), "target": _ang(u, pos.target[k]),
                         "achieved": _ang(u, pos.achieved[k]), "error": _dang(u, err[k])})
        elif pos.kind == "slider":  # slider-crank: slider positions, length unit
            achieved = float(pos.achieved[k])
            rows.append({"input": _ang(u, pos.input[k]), "target": float(pos.target[k]),
                         "achieved": snap(achieved, length_scale) if math.isfinite(achieved) else None,
                         "error": float(err[k]) if math.isfinite(err[k]) else None})
        else:
            rows.append({"input": _ang(u, pos.input[k]),
                         "target": [float(pos.target[k][0]), float(pos.target[k][1])],
                         "achieved": [snap(float(pos.achieved[k][0]), length_scale),
                                      snap(float(pos.achieved[k][1]), length_scale)],
                         "error": float(err[k])})
    return rows


def error_section(solution, u, reference, length_scale: float) -> dict:
    """objective, max, rms (and the gap to a best known value). Round-off is 0: errors below
    NOISE_FLOOR x their scale, an objective below n (NOISE_FLOOR x scale)^2; the gap, a
    relative number, to whole multiples of NOISE_FLOOR."""
    pos = solution.positions
    scale = error_scale(pos, length_scale)
    e = snap(np.abs(np.asarray(pos.error, dtype=float)), scale)
    conv = (lambda x: _dang(u, x)) if pos.kind == "angle" else float
    objective = solution.objective
    if objective is not None:
        objective = snap(objective, len(e) * NOISE_FLOOR * scale * scale)
    out = {"objective": objective, "max": conv(e.max()),
           "rms": conv(math.sqrt(float(np.mean(e * e))))}
    if reference is not None and objective is not None:
        out["best_known"] = reference.objective
        out["gap"] = gap(objective, reference.objective)
    return out
