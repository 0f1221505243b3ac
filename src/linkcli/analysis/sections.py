"""Problem + Solution -> report: an ordered dict of output-ready sections (docs/format.md, Output).

Angles leave here in the file's angle unit, wrapped to (-180, 180] deg where they are
positions; lengths in the file's length unit. Only the sections the problem asks for
(`meta.sections`) are computed. Rounding is the writers' job (export.py).
"""

from __future__ import annotations

import math

import numpy as np

from linkcli import mechanisms
from linkcli.analysis.motion_study import motion_study
from linkcli.mechanisms.columns import angle_out as _ang
from linkcli.mechanisms.columns import turn_out as _dang
from linkcli.noise import NOISE_FLOOR, quantize, snap
from linkcli.reading.meta import ALL_SECTIONS
from linkcli.solution import MESSAGES, Solution


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
    mech = None if solution.linkage is None else mechanisms.of(solution.linkage)
    if mech is not None:
        _linkage_sections(rep, problem, solution, mech, want, notes)
    if mech is not None and getattr(meta, "dynamics", None) is not None:  # [dynamics]: docs/dynamics.md
        from linkcli.analysis.dynamics.sections import add_sections
        short = add_sections(rep, problem, mech, notes)  # (status, message) when it falls short
        if short and rep["status"] == "ok":
            rep["status"], rep["message"] = short
        elif short:
            notes.append(short[1])
    if "strength" in rep:
        from linkcli.analysis.strength import shortfall
        below = shortfall(rep["strength"], u.angle)
        if below and rep["status"] == "ok":
            rep["status"], rep["message"] = "infeasible", below
        elif below:
            notes.append(below)
    if solution.positions is not None and "positions" in want:
        rep["positions"] = position_rows(solution.positions, u, linkage_scale(solution.linkage))
    if solution.positions is not None and "error" in want:
        rep["error"] = error_section(solution, u, meta.reference, linkage_scale(solution.linkage))
    for name, section in solution.sections.items():
        if name in want or name not in ALL_SECTIONS:
            rep[name] = section
    if "tolerance" in want and meta.tolerance is not None and mech is not None:
        from linkcli.analysis import tolerance_report
        from linkcli.analysis.allocation import shortfall as allocation_shortfall
        rep["tolerance"] = tolerance_report.analyse(problem, solution)
        short = allocation_shortfall(rep["tolerance"])  # tolerances that miss their limit: a status
        if short and rep["status"] == "ok":
            rep["status"], rep["message"] = "infeasible", short
        elif short:
            notes.append(short)
    if "solver" in want and solution.solver is not None:
        rep["solver"] = solution.solver.report()
        if meta.reference is not None and solution.objective is not None:
            rep["solver"]["best_known"] = meta.reference.objective
            rep["solver"]["gap"] = rep.get("error", {}).get("gap", gap(solution.objective, meta.reference.objective))
    if notes:
        rep["notes"] = notes
    return rep


def _linkage_sections(rep, problem, solution, mech, want, notes) -> None:
    """linkage, grashof, transmission, motion, kinematics and forces of the solved linkage,
    from its mechanism's home (mechanisms.protocol); only those asked for are computed."""
    u = problem.meta.units
    if "lengths" in want:
        rep["linkage"] = mech.lengths_section(u)
    if "grashof" in want:
        rep["grashof"] = mech.class_section(u)
    notes.extend(mech.linkage_notes(want, u))
    near = solution.working_span[0] if solution.working_span else None
    study = None
    if want & {"transmission", "motion", "kinematics"}:
        study = mech.study(near)
        if study is None:
            notes.append(mech.NO_ASSEMBLY)
    if study is not None and "transmission" in want:
        rep["transmission"] = mech.transmission_section(study, solution.working_span, u, notes)
    if study is not None and "motion" in want:
        rep["motion"] = mech.motion_section(study, u)
    speed, steps = motion_study(problem, u)
    if "motion" in rep and (speed, steps) != motion_study(None, u):  # a study the file set: a result keeps it
        rep["motion"].update(mech.study_keys(speed, steps, u))
    if study is not None and "kinematics" in want:
        rep.setdefault("motion", {}).update(mech.study_keys(speed, steps, u))  # to reproduce it (before
        # kinematics, in the report's order, when motion itself was not asked for)
        rep["kinematics"] = mech.kinematics_rows(study, speed, steps, u)
    if "forces" in want and problem.meta.loads is not None:
        from linkcli.analysis import forces
        if study is None and not want & {"transmission", "motion", "kinematics"}:
            study = mech.study(near)
        if study is not None:
            computed = forces.study_rows(mech, study, speed, steps, problem.meta.loads, u)
            rep.update(forces.echo(problem.meta.loads))  # the load case as given: a result file round-trips
            rep["forces"] = forces.section(mech, study, speed, steps, problem.meta.loads, u, notes,
                                           computed)
            if "motion" in rep:
                rep["motion"].update(mech.study_keys(speed, steps, u))
            if "strength" in want and problem.meta.strength is not None:
                from linkcli.analysis import strength
                rep["strength"] = strength.section(mech, computed, speed, problem.meta, notes)


def linkage_scale(linkage) -> float:
    """The linkage's size, the scale of its length errors (1 without a linkage)."""
    return 1.0 if linkage is None else mechanisms.of(linkage).size()


def gap(value: float, best: float) -> float:
    """Relative gap to the best known value: (value - best) / |best| (absolute if best = 0),
    to whole multiples of the noise floor (its digits below are round-off)."""
    return quantize((value - best) / abs(best) if best != 0 else value - best)


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
