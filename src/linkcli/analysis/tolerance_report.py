"""The `tolerance` report section (docs/tolerance.md, [tolerance]): the Monte Carlo study of
a solved linkage (analysis.tolerance draws and counts), its inverse mode (the largest common
tolerance, analysis.inverse_search), the least-cost allocation (analysis.allocation) and the
compared schemes (analysis.schemes), and the ISO 286 fit rows. numpy only.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.analysis.made_parts import FitZones, Parts
from linkcli.analysis.tolerance import Model, chunks, failures, plan_of, row_section, run, run_rows, wilson
from linkcli.model import InverseTolerance, Tolerance
from linkcli.noise import snap


def analyse(problem, solution) -> dict:
    """The `tolerance` report section of a solved linkage: output-ready (plain floats, angles
    in the file's unit, lengths in its length unit)."""
    from linkcli.mechanisms import of
    from linkcli.reading.tolerance_lengths import check_lengths
    model = of(solution.linkage).tolerance_model(problem, solution)
    problem = with_links(problem, model.known)
    check_lengths(problem.meta, model.known, complete=True)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        return _analyse(problem, model)


def _analyse(problem, model: Model) -> dict:
    from linkcli.analysis.made_parts import parts as made_parts
    tol: Tolerance = problem.meta.tolerance
    units = problem.meta.units
    seed = int(problem.meta.solver.seed)
    conv = (lambda x: float(units.from_rad(x))) if model.kind == "angle" else float
    opt = (lambda x: None if x is None or not math.isfinite(x) else conv(x))
    level = tol.max_failure_probability if isinstance(tol, InverseTolerance) else None
    parts = made_parts(model, problem)
    lengths = {k: float(v) for k, v in tol.lengths.items()}
    general = resolved_general(model, parts, tol.general)
    for key in set(tol.general) - set(general):  # given per distance (resolved_general)
        lengths.pop(key, None)
    lengths.update(general)
    out: dict = {"measure": model.measure, "samples": tol.samples, "distribution": tol.distribution,
                 "lengths": dict(lengths), "clearance": "fits" if tol.clearance_fits else float(tol.clearance),
                 **model.given(tol)}
    if tol.general:
        out["general_tolerances"] = {k: f"ISO 2768-{c}" for k, c in tol.general.items()}
    if isinstance(parts.clearance, FitZones) or isinstance(parts.play, FitZones):
        out["fits"] = fit_rows(problem, parts)
    if len(model.inputs) == 0:
        out["message"] = model.no_assembly
        return out
    plan = plan_of(model, parts, tol.samples, tol.distribution)
    passes: dict = {}
    allocation = None
    if tol.cost is not None and level is not None:
        from linkcli.analysis.allocation import allocation_section
        allocation = allocation_section(problem, model, parts, level)
    if level is not None:
        from linkcli.analysis.inverse_search import Search, largest_tolerance
        search = Search(model, parts, plan, seed, tol.allowed_error)
        given = max((float(x) for k, x in zip(model.columns, parts.scale) if k in model.inverse), default=0.0)
        t, p_t = largest_tolerance(search, level, given, model.cap)
        passes = {tuple(search.unit * x): v for x, v in search.passes.items()}
        if not tol.lengths_given:  # no tolerance written: report the study at the one found
            # (a written 0, exact parts, is a study of its own and is reported as 0), or at
            # the least-cost ones
            found = {row["link"]: row["tolerance"] for row in allocation["links"]} if allocation else {}
            lengths = {k: found.get(k, t) for k in model.inverse}
            out["lengths"] = dict(lengths)
            parts = parts.with_scale(np.where(search.unit > 0, [lengths.get(c, 0.0) for c in model.columns],
                                              parts.scale))
    draws = None
    if getattr(model, "per_row", False):  # every row's error too (the five-bar's path)
        draws = run_rows(model, chunks(seed, plan), parts)
        err, ok = draws.err, draws.ok
    else:
        err, ok = passes.get(tuple(parts.scale)) or run(model, chunks(seed, plan), parts)
    out.update(study(model, err, ok, tol.samples, tol.allowed_error, opt,
                     model.no_allowed_error if tol.allowed_error is None else None))
    out["sensitivity"] = {key: opt(s) for key, s in model.sensitivity().items()}
    if level is not None:
        out["max_failure_probability"] = float(level)
        out["largest_tolerance"] = float(t)
        out["failure_probability_at_largest"] = float(p_t)
    if draws is not None:
        out.update(row_section(model, draws, tol.allowed_error, tol.samples, conv))
    if allocation is not None:
        out["allocation"] = allocation
    if tol.schemes:
        from linkcli.analysis.schemes import schemes_section
        out["schemes"] = schemes_section(problem, model, level, opt)
    return out


def study(model: Model, err: np.ndarray, ok: np.ndarray, n: int, allowed: float | None, opt,
          failure: str | None = None) -> dict:
    """The statistics of one study: nominal error, error mean, p95, max over the samples that
    assemble, (`failure`: what a failure is without an allowed error), assembly failures,
    failure probability with its standard error and Wilson interval."""
    nominal, _ = model.errors(np.zeros((1, len(model.columns))), None, None)
    good = snap(err[ok], model.scale)  # round-off of an exact design (exact parts) is 0
    k = failures(err, ok, allowed)
    p = k / n
    lo, hi = wilson(k, n)
    return {
        "nominal_error": opt(snap(float(nominal[0]), model.scale)),
        "error_mean": opt(float(good.mean())) if good.size else None,
        "error_p95": opt(float(np.percentile(good, 95))) if good.size else None,
        "error_max": opt(float(good.max())) if good.size else None,
        "allowed_error": opt(allowed),
        **({"failure": failure} if failure else {}),
        "assembly_failures": int(n - good.size),
        "failure_probability": p,
        "failure_probability_se": math.sqrt(p * (1.0 - p) / n),
        "failure_probability_ci95": [lo, hi],
    }


def with_links(problem, known: dict):
    """`problem` with its [tolerance] written for every link (model.tolerance.for_links) on the
    links of `known` (a design's, with "ground"); `problem` itself otherwise."""
    from dataclasses import replace

    from linkcli.model.tolerance import for_links
    tol = problem.meta.tolerance
    if tol is None or tol.every is None:
        return problem
    return replace(problem, meta=replace(problem.meta, tolerance=for_links(tol, tuple(known))))


def resolved_general(model: Model, parts: Parts, general: dict) -> dict:
    """key -> the +- tolerance its ISO 2768 class gave (length unit); where the class gives a
    key's columns different ones (a drawn link's distances, each at its own size), each
    column by its own name ("rocker O4-C", as `sensitivity`): one value for the link was the
    last distance's (rocker 0.3 where its 25 mm distance got 0.2)."""
    from linkcli.analysis.made_parts import column_key
    by_key: dict = {}
    for c, v in zip(model.columns, parts.scale):
        key = column_key(model, c)
        if key in general:
            by_key.setdefault(key, []).append((c, float(v)))
    out = {}
    for key, values in by_key.items():
        if len({v for _, v in values}) == 1:
            out[key] = values[0][1]
        else:
            out.update(values)
    return out


def fit_rows(problem, parts: Parts) -> list[dict]:
    """One row per fitted joint: fit, diameter (length unit), the hole's and the shaft's
    deviations (um, ISO 286) and the radial clearance range (length unit)."""
    from linkcli.standards import iso286
    joints = {j.name: j for j in problem.meta.joints}
    mm = problem.meta.units.mm_per_length
    rows, seen = [], set()
    for zones in (parts.clearance, parts.play):
        if not isinstance(zones, FitZones):
            continue
        for name, text in zip(zones.names, zones.fits):
            if name in seen:  # a drawn pin of three bodies: two bearings, one fit
                continue
            seen.add(name)
            fit = iso286.limits(text, joints[name].diameter * mm)
            least, largest = fit.clearance
            rows.append({"joint": name, "fit": text, "diameter": joints[name].diameter,
                         "hole_um": [fit.hole.lower, fit.hole.upper],
                         "shaft_um": [fit.shaft.lower, fit.shaft.upper],
                         "radial_clearance": [least / 2e3 / mm, largest / 2e3 / mm]})
    return rows
