"""Function generation's own report sections, in the file's units: `target` (the law's
start angles, sweeps and points) and `structural_error` (the error over the whole sweep,
not only at the evaluation points). The sections every linkage shares are
linkcli.analysis.sections."""

from __future__ import annotations

import math

import numpy as np

from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.noise import first_max, snap
from linkcli.types.function_generation.model import Model

CURVE_ROWS = 41  # rows of the structural-error curve in the report
DENSE = 1001  # points of the structural-error summary over the sweep


def report_tables(name: str, section, length_unit: str, angle_unit: str) -> list:
    """No tailored tables: the generic layout of linkcli.report serves these sections."""
    return []


def target_section(problem, phi0: float, psi0: float, u) -> dict:
    out = {"input_start": float(u.from_rad(float(kin.wrap(phi0))))}
    if problem.form == "function" or problem.start == "extended" or problem.law.uses("psi0"):
        out["output_start"] = float(u.from_rad(float(kin.wrap(psi0))))
    out["input_sweep"] = float(u.from_rad(problem.input_sweep))
    if problem.form == "function":
        out["output_sweep"] = float(u.from_rad(problem.output_sweep))
        out["x"] = [float(problem.x_range[0]), float(problem.x_range[1])]
    out["points"] = len(problem.fractions)
    out["spacing"] = problem.spacing
    return out


def dense_target(problem, model: Model, s, phi, phi0, psi0):
    """psi_target at fractions s of the sweep (any s, not only the evaluation points)."""
    if problem.form == "function":
        x0, x1 = problem.x_range
        law = problem.law
        with np.errstate(all="ignore"):
            f0, f1 = law.scalar(x=x0), law.scalar(x=x1)
            y = law(x=x0 + s * (x1 - x0))
            return psi0 + (y - f0) / (f1 - f0) * problem.output_sweep
    with np.errstate(all="ignore"):
        return model.target(phi, phi0, psi0)


def structural_error(problem, model: Model, lengths, starts, sign, u) -> dict:
    """The error over the whole sweep, not only at the points: max and rms over DENSE
    points, and a plot-ready curve of CURVE_ROWS rows (input, error). `lengths` are
    (a, b, c, d), `starts` (phi0, psi0) in rad."""
    a, b, c, d = lengths
    phi0, psi0 = starts
    s = np.linspace(0.0, 1.0, DENSE)
    phi = phi0 + s * problem.input_sweep
    target = dense_target(problem, model, s, phi, phi0, psi0)
    with np.errstate(all="ignore"):
        p = kin.pose(a, b, c, d, phi, sign)
        ok = np.isfinite(target) & p.valid & np.isfinite(p.psi)
        err = snap(np.where(ok, kin.wrap(np.where(ok, p.psi - target, 0.0)), np.nan), 1.0)
    k = int(first_max(np.abs(err))) if ok.any() else 0  # equal maxima: the first along the sweep
    rows = []
    for i in np.linspace(0, DENSE - 1, CURVE_ROWS).round().astype(int):
        e = err[i]
        rows.append({"input": float(u.from_rad(float(kin.wrap(phi[i])))),
                     "error": float(u.from_rad(e)) if math.isfinite(e) else None})
    fin = err[np.isfinite(err)]
    return {"max": float(u.from_rad(abs(err[k]))) if ok.any() else None,
            "input_at_max": float(u.from_rad(float(kin.wrap(phi[k])))),
            "rms": float(u.from_rad(math.sqrt(float(np.mean(fin * fin))))) if fin.size else None,
            "samples": DENSE, "curve": rows}
