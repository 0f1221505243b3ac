"""quick-return's own report sections, in the file's units, and their table layout.

- `design`: the chosen member's free parameter, its worst transmission angle, and the time
  ratio and swing (or stroke) recomputed from its lengths (simulate.py: dead centres by the
  cosine rule), not echoed from the file.
- `family`: rows across the free parameter (lengths, worst transmission angle, inside the
  window or not) with the chosen member inserted in parameter order and marked.
The linkage, class, transmission, motion and kinematics sections are the shared ones
(linkcli.analysis.sections, slider_sections) of the linkage the solver returns.
"""

from __future__ import annotations

import numpy as np

from linkcli.io.tables import KeyValues, Rows
from linkcli.mechanisms.four_bar.kinematics import wrap
from linkcli.noise import snap

from . import family, simulate, transmission

FAMILY_ROWS = family.TABLE_ROWS


def _angle(u, x: float) -> float:
    """A position angle in the file's unit, wrapped to (-180, 180] deg; round-off of 0 is 0."""
    return float(u.from_rad(snap(float(wrap(x)), 1.0)))


def design_section(problem, design) -> dict:
    """mechanism, parameter, worst_transmission and the recomputed time ratio with the swing
    (crank-rocker) or stroke (slider-crank)."""
    u = problem.meta.units
    L = design.lengths
    out = {"mechanism": design.mechanism, "parameter": design.parameter}
    if design.mechanism == "crank-rocker":
        ratio, swing = simulate.simulate_time_ratio_and_swing(
            L["input"], L["coupler"], L["output"], L["ground"])
        out.update(time_ratio=ratio, swing=float(u.from_rad(swing)))
    else:
        stroke, ratio = simulate.simulate_stroke_and_time_ratio(L["input"], L["coupler"], L["offset"])
        out.update(time_ratio=ratio, stroke=stroke)
    out["worst_transmission"] = float(u.from_rad(design.worst_transmission))
    return out


def family_rows(problem, design, table: dict, window) -> list[dict]:
    """The family table (family.crank_rocker_family / slider_crank_family columns) as rows,
    the chosen member inserted in parameter order with chosen = true; `inside_window` when
    the problem has a transmission window."""
    u = problem.meta.units
    names = family.FOUR_BAR if design.mechanism == "crank-rocker" else family.SLIDER
    rho = np.asarray(table["parameter"], dtype=float)
    k = int(np.searchsorted(rho, design.parameter))
    columns = {"parameter": np.insert(rho, k, design.parameter)}
    for n in names:
        columns[n] = np.insert(np.asarray(table[n], dtype=float), k, design.lengths[n])
    mu = np.insert(np.asarray(table["worst_transmission"], dtype=float), k, design.worst_transmission)
    rows = []
    for i in range(len(mu)):
        row = {name: float(col[i]) for name, col in columns.items()}
        row["worst_transmission"] = float(u.from_rad(mu[i]))
        if window is not None:
            row["inside_window"] = bool(window_miss(design.mechanism, {n: columns[n][i] for n in names},
                                                    window) == 0.0)
        row["chosen"] = i == k
        rows.append(row)
    return rows


def window_miss(mechanism: str, lengths: dict, window) -> float:
    """How far (rad) the transmission angle over the full turn leaves the window (0: inside;
    round-off below the noise floor of 1 rad counts as inside)."""
    L = lengths
    if mechanism == "crank-rocker":
        m = transmission.four_bar_margins(L["input"], L["coupler"], L["output"], L["ground"], window)
    else:
        m = transmission.slider_margins(L["input"], L["coupler"], L["offset"], window)
    return snap(max(0.0, -float(np.min(m))), 1.0)


# ---------------------------------------------------------------- table layout

def report_tables(name: str, section, length_unit: str, angle_unit: str) -> list:
    """`design` as a key/value table with units, `family` as rows with units in the
    headings; [] for any other section (the generic layout)."""
    lu, au = length_unit, angle_unit
    if name == "design" and isinstance(section, dict):
        labels = {"parameter": "free parameter", "time_ratio": "time ratio K (recomputed)",
                  "swing": f"swing ({au}, recomputed)", "stroke": f"stroke ({lu}, recomputed)",
                  "worst_transmission": f"worst transmission angle ({au})"}
        return [KeyValues("Design", [(labels.get(k, k.replace("_", " ")), v) for k, v in section.items()])]
    if name == "family" and isinstance(section, list) and section:
        heads = {"parameter": "parameter", "input": f"input ({lu})", "coupler": f"coupler ({lu})",
                 "output": f"output ({lu})", "ground": f"ground ({lu})", "offset": f"offset ({lu})",
                 "worst_transmission": f"worst mu ({au})", "inside_window": "in window",
                 "chosen": "chosen"}
        rows = [{k: ("<-" if v is True and k == "chosen" else "" if k == "chosen" else v)
                 for k, v in r.items()} for r in section]
        return [Rows("Family across the free parameter (chosen member marked)", rows, heads)]
    return []
