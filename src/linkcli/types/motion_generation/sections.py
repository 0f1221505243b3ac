"""Motion generation's own report sections, in the file's units: `positions` (per pose:
input angle, target and achieved pose [x, y, angle], position and angle error), `error`
(objective, largest and rms position and angle errors, the angle weight), `candidates`
(each candidate linkage with its pivots, lengths, class, working transmission and
defects), `candidate_counts` (searched families: how many candidates have each defect)
and `burmester` (five poses: the real Burmester dyads). Round-off is 0 (linkcli.noise):
errors against the linkage's size (lengths) or 1 rad (angles).
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.analysis.sections import gap
from linkcli.io.tables import KeyValues, Rows
from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.noise import NOISE_FLOOR, snap

from .screen import DEFECTS


def report_tables(name: str, section, length_unit: str, angle_unit: str) -> list:
    """`candidates` and `burmester` as tables; the generic layout serves the rest."""
    if name == "candidates" and isinstance(section, list):
        return [Rows(f"Candidates ({length_unit}, {angle_unit})", section)]
    if name == "burmester" and isinstance(section, dict):
        if not section["dyads"]:
            return [KeyValues("Burmester dyads", [("real dyads", section["real_dyads"])])]
        return [Rows(f"Burmester dyads ({length_unit}): {section['real_dyads']} real", section["dyads"])]
    return []


def _ang(u, x) -> float:
    return float(u.from_rad(snap(float(kin.wrap(x)), 1.0)))


def _pt(v, size) -> list[float]:
    return [snap(float(v[0]), size), snap(float(v[1]), size)]


def position_rows(phi, target, achieved, pos, ang, u, size) -> list[dict]:
    """One row per pose: input, target [x, y, angle], achieved [x, y, angle], position_error,
    angle_error (achieved minus target, wrapped)."""
    pos = snap(np.asarray(pos, float), size)
    ang = snap(np.asarray(ang, float), 1.0)
    return [{"input": _ang(u, phi[k]),
             "target": [float(target[k][0]), float(target[k][1]), _ang(u, target[k][2])],
             "achieved": _pt(achieved[k], size) + [_ang(u, achieved[k][2])],
             "position_error": float(pos[k]), "angle_error": float(u.from_rad(float(ang[k])))}
            for k in range(len(phi))]


def error_section(objective, pos, ang, weight, u, size, reference) -> dict:
    """objective = sum |P_i - T_i|^2 + (w dangle_i)^2 (length unit^2), max and rms of the
    position and angle errors, the angle weight w."""
    pos = snap(np.abs(np.asarray(pos, float)), size)
    ang = snap(np.abs(np.asarray(ang, float)), 1.0)
    objective = snap(objective, len(pos) * NOISE_FLOOR * size * size)
    out = {"objective": objective, "max_position_error": float(pos.max()),
           "rms_position_error": math.sqrt(float(np.mean(pos * pos))),
           "max_angle_error": float(u.from_rad(float(ang.max()))),
           "rms_angle_error": float(u.from_rad(math.sqrt(float(np.mean(ang * ang))))),
           "angle_weight": float(weight)}
    if reference is not None:
        out["best_known"] = reference.objective
        out["gap"] = gap(objective, reference.objective)
    return out


def candidate_rows(res, params, g1, m1, g2, m2, order, u, family) -> list[dict]:
    """Rows of the listed candidates (indices `order`): the dyads (Burmester: their
    numbers), A0, B0 (global), A, B (body frame), lengths, class, the working transmission
    range and the defects ("none" when there is none)."""
    rows = []
    for k in order:
        p = params[k]
        size = float(max(p[3:7]))
        row = {"candidate": int(k) + 1}
        row.update({"A0": _pt(g1[k], size), "B0": _pt(g2[k], size), "A": _pt(m1[k], size),
                    "B": _pt(m2[k], size), "ground": float(p[3]), "input": float(p[4]),
                    "coupler": float(p[5]), "output": float(p[6]),
                    "class": kin.GRASHOF_CLASSES[int(kin.grashof_code(p[4], p[5], p[6], p[3]))],
                    "transmission": [float(u.from_rad(res["mu_min"][k])), float(u.from_rad(res["mu_max"][k]))],
                    "defects": ", ".join(n for n in DEFECTS if bool(res["defects"][n][k])) or "none"})
        rows.append(row)
    if family == "burmester":
        k_dyads = _dyad_numbers(g1, m1)
        for row, k in zip(rows, order):
            row["dyads"] = [k_dyads[0][k] + 1, k_dyads[1][k] + 1]
    return rows


def _dyad_numbers(g1, m1):
    """Burmester pairs are generated as every ordered (i, j), i != j: recover i and j."""
    total = len(g1)
    n = int(round((1 + math.sqrt(1 + 4 * total)) / 2))
    i, j = np.nonzero(~np.eye(n, dtype=bool))
    return i, j


def defect_counts(res) -> dict:
    """Searched families: the number of candidates and how many have each defect."""
    out = {"total": int(len(res["count"])), "defect_free": int(np.sum(res["count"] == 0))}
    out.update({name: int(np.sum(res["defects"][name])) for name in DEFECTS})
    return out


def burmester_section(ground, moving, u) -> dict:
    """The real Burmester dyads (ground pivot, global; moving pivot, body frame), numbered
    in the order found; `real_dyads` may be 0."""
    n = len(ground)
    ground, moving = np.asarray(ground, float).reshape(n, 2), np.asarray(moving, float).reshape(n, 2)
    size = float(np.max(np.abs(np.concatenate([ground, moving])))) if n else 1.0
    return {"real_dyads": n, "dyads": [{"dyad": k + 1, "ground": _pt(ground[k], size),
                                        "moving": _pt(moving[k], size)} for k in range(n)]}


def polished_rows(candidates, u) -> list[dict]:
    """Least squares: every distinct polished design, best first (feasible first, then
    objective); starts that reached the same design (parameters within 1e-6 relative of
    the linkage's size) are listed once."""
    rows, kept = [], []
    for c in candidates:
        p = np.asarray(c["params"], float)
        size = float(max(p[3:7]))
        if any(np.max(np.abs(p - q)) <= 1e-6 * size for q in kept):
            continue
        kept.append(p)
        rows.append({"objective": float(c["objective"]), "branch": c["branch"], "ground": float(p[3]),
                     "input": float(p[4]), "coupler": float(p[5]), "output": float(p[6]),
                     "defects": c["why"] or "none"})
    return rows
