"""The flipper's own report sections, in the file's units: `cylinder` (the design, its
peak force, lengths, pressures, margins and the force over the sweep) and `pareto` (the
force/size trade-off rows); and how the table report lays them out (`report_tables`).
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.io.tables import KeyValues, Rows
from linkcli.noise import snap
from linkcli.types.flipper_cylinder.statics import Statics


def facts(problem, statics: Statics, design) -> dict:
    """Everything reported about one design (radians, the file's length unit, N). The
    lengths are the true extremes over the sweep (L turns back where the cylinder line
    crosses the hinge); a design that cannot hold the platform somewhere (`crosses`) has
    an infinite peak at that angle."""
    p = np.asarray(design, dtype=float)[None, :]
    sing = statics.singular(p)
    closed, opened, closed_at = (float(x[0]) for x in statics.lengths(p, sing=sing))
    ls, le = (float(x[0]) for x in statics.end_lengths(p))
    t0 = float(sing["tau0"][0])
    turns = bool(sing["crosses"][0]) and 0.0 < t0 < statics.sweep  # L has an interior extreme
    if turns:  # d(L^2)/dt = 2 K: the rod extends while K > 0
        k_start = float(statics.terms(p, np.array([0.0]))[0][0, 0])
        motion = "extends, then retracts" if k_start > 0 else "retracts, then extends"
    else:
        motion = "extends" if le > ls else "retracts"
    out = {"design": p[0], "crosses": bool(sing["blocked"][0]), "min_length": closed,
           "max_length": opened, "stroke": opened - closed, "rod_motion": motion,
           "closed_at": closed_at, "cross_at": t0, "zero_length": bool(sing["meet"][0]),
           "load_moment": float(sing["moment"][0])}
    pk = statics.peaks(p)
    for k in ("push", "push_at", "pull", "pull_at", "peak", "peak_at"):
        out[k] = float(pk[k][0])
    out["is_push"] = bool(pk["is_push"][0])
    return out


def _nice_step(span: float) -> float:
    """The smallest of 1, 2, 5 x 10^k that cuts `span` into at most 20 steps."""
    for k in range(-6, 7):
        for m in (1.0, 2.0, 5.0):
            step = m * 10.0 ** k
            if span / step <= 20.0 + 1e-9:
                return step
    return span


def table_angles(problem) -> np.ndarray:
    """Platform angles (file unit) of the force table: start, the multiples of the step
    strictly inside the sweep, end."""
    u = problem.meta.units
    a, b = _file_angle(problem, "start"), _file_angle(problem, "end")
    step = float(u.from_rad(problem.table_step)) if problem.table_step else _nice_step(b - a)
    eps = 1e-9 * max(abs(step), 1.0)
    k0, k1 = math.floor(a / step + 1e-9) + 1, math.ceil(b / step - 1e-9) - 1
    inner = [float(f"{k * step:.12g}") for k in range(k0, k1 + 1) if a + eps < k * step < b - eps]
    return np.array([a] + inner + [b])


def _file_angle(problem, key: str) -> float:
    """`start` or `end` in the file's unit, as written (no round trip through radians)."""
    u = problem.meta.units
    value = float(u.from_rad(getattr(problem, key)))
    return float(f"{value:.15g}")  # the ulp of the round trip through radians


def force_rows(problem, statics: Statics, design, angles) -> list[dict]:
    """Rows angle (file unit, as given), force (N; None where no finite force holds the
    platform: the cylinder line through the hinge), arm and length (length unit)."""
    u = problem.meta.units
    angles = np.asarray(angles, dtype=float)
    tau = np.array([u.to_rad(float(x)) for x in angles]) - problem.start
    tau[0], tau[-1] = max(tau[0], 0.0), min(tau[-1], statics.sweep)
    force, arm, length = (x[0] for x in statics.forces(np.asarray(design, dtype=float)[None, :], tau))
    shown = -angles if problem.clockwise else angles  # sweep order: start first, as written
    return [{"angle": float(shown[i]) + 0.0, "force": float(force[i]) if math.isfinite(force[i]) else None,
             "arm": float(arm[i]), "length": float(length[i])} for i in range(len(tau))]


def full_angles(problem, statics: Statics) -> np.ndarray:
    """The sweep grid in the file's unit, ends as given."""
    a, b = _file_angle(problem, "start"), _file_angle(problem, "end")
    out = a + (b - a) * (statics.grid / statics.sweep)
    out[0], out[-1] = a, b
    return out


def shown_point(problem, x, y, scale: float) -> list[float]:
    """A pivot [x, y] in the file's frame (a clockwise sweep is solved mirrored in x); a
    coordinate that is round-off against `scale` (the design's largest coordinate) is 0
    (linkcli.noise: a pivot on a bound at 0 printed -2.13e-14)."""
    return [snap(float(problem.shown_x(float(x))), scale), snap(float(y), scale)]


def shown_angle(problem, tau: float) -> float:
    """A platform angle of the sweep in the file's unit; round-off of 0 (against 1 rad) is 0."""
    return float(problem.meta.units.from_rad(snap(problem.shown_angle(problem.start + tau), 1.0))) + 0.0


def _scale(design) -> float:
    return float(np.max(np.abs(np.asarray(design, dtype=float))))


def cylinder_section(problem, statics: Statics, f: dict) -> dict:
    """The `cylinder` report section, output-ready (docs/format.md, Output)."""
    u = problem.meta.units
    p = f["design"]

    def ang(tau):
        return shown_angle(problem, tau)

    kind = "unbounded" if f["crosses"] else ("push" if f["is_push"] else "pull")
    size = _scale(p)
    sec = {"rod_pivot": shown_point(problem, p[0], p[1], size), "base_pivot": shown_point(problem, p[2], p[3], size),
           "peak_force": f["peak"], "peak_angle": ang(f["peak_at"]), "peak_kind": kind,
           "push_force": f["push"], "push_angle": ang(f["push_at"]) if f["push"] > 0 else None,
           "pull_force": f["pull"], "pull_angle": ang(f["pull_at"]) if f["pull"] > 0 else None,
           "min_length": f["min_length"], "max_length": f["max_length"], "stroke": f["stroke"],
           "rod_motion": f["rod_motion"]}
    mm = u.mm_per_length
    if problem.bore is not None:
        bore_area = math.pi / 4.0 * (problem.bore * mm) ** 2  # mm^2: N / mm^2 = MPa
        sec["bore"] = problem.bore
        if problem.rod is not None:
            sec["rod"] = problem.rod
        sec["push_pressure"] = f["push"] / bore_area
        if problem.rod is not None:
            annulus = bore_area - math.pi / 4.0 * (problem.rod * mm) ** 2
            sec["pull_pressure"] = f["pull"] / annulus
    if problem.dead_length is not None:
        sec["dead_length"] = problem.dead_length
        # a margin of round-off (a design on its limit) is 0 (linkcli.noise)
        sec["dead_length_margin"] = snap(f["min_length"] - f["stroke"] - problem.dead_length, f["max_length"])
    if problem.max_force is not None:
        sec["max_force"] = problem.max_force
        sec["force_margin"] = snap(problem.max_force - f["peak"], problem.max_force)
    sec["forces"] = force_rows(problem, statics, p, table_angles(problem))
    sec["forces_full"] = force_rows(problem, statics, p, full_angles(problem, statics))
    return sec


def pareto_rows(problem, statics: Statics, designs) -> list[dict]:
    rows = []
    for design in designs:
        f = facts(problem, statics, design)
        size = _scale(design)
        rows.append({"closed_length": f["min_length"], "peak_force": f["peak"],
                     "peak_angle": shown_angle(problem, f["peak_at"]),
                     "peak_kind": "push" if f["is_push"] else "pull", "stroke": f["stroke"],
                     "max_length": f["max_length"], "rod_pivot": shown_point(problem, design[0], design[1], size),
                     "base_pivot": shown_point(problem, design[2], design[3], size)})
    return rows


PARETO_COLUMNS = {"closed_length": "closed length", "peak_force": "peak force (N)", "peak_angle": "at",
                  "peak_kind": "push/pull", "stroke": "stroke", "rod_pivot": "rod pivot A",
                  "base_pivot": "base pivot C"}


def report_tables(name: str, section, length_unit: str, angle_unit: str) -> list:
    """The table report's layout of `cylinder` (a key/value table with units and the force
    table; `forces_full`, the full-resolution sweep, is left to JSON and TOML) and of the
    `pareto` rows; [] for any other section (the generic layout)."""
    lu, au = length_unit, angle_unit
    if name == "pareto" and isinstance(section, list) and section:
        return [Rows(f"Trade-off: least peak force for each closed length ({lu}, {au}; "
                     "max length = closed + stroke)",
                     [{k: r.get(k) for k in PARETO_COLUMNS} for r in section], PARETO_COLUMNS, no_wrap=True)]
    if name != "cylinder" or not isinstance(section, dict):
        return []
    labels = {"rod_pivot": f"rod pivot A at start ({lu})", "base_pivot": f"base pivot C ({lu})",
              "peak_force": "peak force (N)", "peak_angle": f"peak at platform angle ({au})",
              "peak_kind": "peak is a", "push_force": "largest push (N)", "push_angle": f"largest push at ({au})",
              "pull_force": "largest pull (N)", "pull_angle": f"largest pull at ({au})",
              "min_length": f"closed length, min ({lu})", "max_length": f"max length ({lu})",
              "stroke": f"stroke ({lu})", "rod_motion": "rod (start to end)", "bore": f"bore ({lu})",
              "rod": f"rod ({lu})", "push_pressure": "push pressure on bore (MPa)",
              "pull_pressure": "pull pressure on annulus (MPa)", "dead_length": f"dead length ({lu})",
              "dead_length_margin": f"closed - stroke - dead length ({lu})",
              "max_force": "max force (N)", "force_margin": "max force - peak (N)"}
    rows = [(labels.get(k, k.replace("_", " ")), v) for k, v in section.items()
            if not (isinstance(v, list) and v and isinstance(v[0], dict))]
    blocks: list = [KeyValues("Cylinder", rows)]
    forces = section.get("forces") or []
    if forces:
        table = [{"angle": r.get("angle"), "force": r.get("force"),
                  "push/pull": ("-" if r.get("force") is None else "push" if r["force"] > 0
                                else "pull" if r["force"] < 0 else "-"),
                  "arm": r.get("arm"), "length": r.get("length")} for r in forces]
        heads = {"angle": f"platform angle ({au})", "force": "force (N)", "arm": f"moment arm ({lu})",
                 "length": f"length C-A ({lu})"}
        full = section.get("forces_full") or []
        full = getattr(full, "total", len(full))  # the table view may hold it cut (linkcli.report.Elided)
        note = f" ({full} angles in JSON/TOML: forces_full)" if full else ""
        blocks.append(Rows(f"Cylinder force over the sweep{note}", table, heads))
    return blocks
