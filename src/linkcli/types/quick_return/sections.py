"""quick-return's own report sections, in the file's units, and their table layout.

- `design`: the chosen member's free parameter, its worst transmission angle, and the time
  ratio and swing (or stroke) recomputed from its lengths (simulate.py: dead centres by the
  cosine rule), not echoed from the file.
- `family`: rows across the free parameter (lengths, worst transmission angle, inside the
  window or not) with the chosen member inserted in parameter order and marked.
- a slider-crank's `linkage`, `transmission` and `motion` (the shared sections,
  linkcli.analysis.sections, know the four-bar only): lengths and offset; the transmission
  angle over the full turn in closed form (transmission.py): mu = atan2(sqrt(b^2 - h^2), |h|),
  h = e - a sin(phi), least where |h| = a + |e| (sin(phi) = -sign(e)), greatest where |h| is
  least (sin(phi) = e / a when |e| <= a, else sin(phi) = sign(e)); the motion from
  linkcli.mechanisms.slider_crank.motion (dead centres in closed form).
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.io.tables import KeyValues, Rows
from linkcli.mechanisms import slider_crank as sc
from linkcli.mechanisms.four_bar import wrap
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


# ---------------------------------------------------------------- slider-crank, shared keys

def slider_linkage(design) -> dict:
    L = design.lengths
    return {"mechanism": "slider-crank", "input": L["input"], "coupler": L["coupler"],
            "offset": L["offset"], "branch": "open"}


def slider_transmission(problem, design) -> dict:
    """min, max and where over the full turn (closed form, module docstring); ties go to the
    first input angle counter-clockwise from 0."""
    u = problem.meta.units
    a, b, e = (design.lengths[k] for k in ("input", "coupler", "offset"))
    mu_min, mu_max = (float(x) for x in transmission.slider_extremes(a, b, e))
    at_min = -0.5 * math.pi if e > 0 else 0.5 * math.pi  # e = 0: both +-90 deg, +90 first
    if abs(e) <= a:
        s = math.asin(e / a)
        at_max = s if e >= 0 else math.pi - s  # first of asin(e/a), pi - asin(e/a) from 0
    else:
        at_max = math.copysign(0.5 * math.pi, e)
    return {"min": float(u.from_rad(mu_min)), "max": float(u.from_rad(mu_max)),
            "input_at_min": _angle(u, at_min), "input_at_max": _angle(u, at_max)}


def slider_motion(problem, design) -> dict:
    """input_full_turn, slider_range, stroke, time_ratio, slow_stroke (mechanisms.slider_crank)."""
    a, b, e = (design.lengths[k] for k in ("input", "coupler", "offset"))
    m = sc.motion(a, b, e, "open")
    lo, hi = m["slider_range"]
    return {"input_full_turn": m["input_full_turn"], "slider_range": [lo, hi],
            "stroke": m["stroke"], "time_ratio": m["time_ratio"], "slow_stroke": m["slow_stroke"]}


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
