"""The `forces` section (docs/loads.md): input torque, pin forces and mechanical advantage at
the motion study's rows, from a problem's [loads] and [masses].

The rows are the kinematics section's (`Study.rows`: the same input angles at the same
constant `[motion] input_speed`); the mechanism's home (`load_rows`) solves the Newton-Euler
equations of all rows in one batched solve and names its pins; this module reduces them to
the load cycle and the report's rows.
Lengths enter in metres whatever the file's unit: torques in N m, forces in N.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from linkcli.analysis.loads import forces_rows, load_cycle
from linkcli.mechanisms.protocol import LoadRows
from linkcli.noise import snap_series
from linkcli.textnum import num

MAX_LISTED = 6  # inputs named in a note; more are counted


def metres_per_unit(units) -> float:
    return units.mm_per_length / 1000.0


def echo(case) -> dict:
    """`loads` and `masses` as given, for the report: `analyze` of a result reads them back."""
    return dict(case.given)


def study_rows(mech, study, speed: float, steps: int, case, units):
    """(phi, inputs, LoadRows): the drive angles (rad) of the motion study's rows, the same as
    printed (the file's angle unit) and the home's inverse dynamics there -- what the
    `forces` and `strength` sections share."""
    phi, shown = study.rows(steps)
    inputs = study.printed(shown, units)
    return phi, inputs, mech.load_rows(phi, speed, case, metres_per_unit(units))


def section(mech, study, speed: float, steps: int, case, units, notes: list,
            computed=None) -> dict:
    """The `forces` section: input_torque {peak, at_input, rms}, pins {name: {max, min, mean,
    amplitude, x: {...}, y: {...}}}, rows [{input, input_torque, pins {name: {x, y,
    magnitude}}, mechanical_advantage}], at the rows of the motion study `study` = (full
    turn, arc); `computed`: its `study_rows` when already solved. A linkage of several
    drives adds each other drive's angle and torque (`<name>`, `<name>_torque`, LoadRows.
    other_drives) and has no mechanical advantage. Notes name the toggles
    (infinite mechanical advantage) and dead points (unbounded forces, left out of the load
    cycle)."""
    _, inputs, rows = computed or study_rows(mech, study, speed, steps, case, units)
    if rows.mechanical_advantage is not None:
        rows = replace(rows, mechanical_advantage=snap_series(rows.mechanical_advantage))
    others = {name: study.printed(shown, units) for name, (shown, _) in rows.other_drives.items()}
    cycle = load_cycle(rows, inputs, others)
    out = {"input_torque": cycle["input_torque"]}
    out.update({f"{name}_torque": cycle[f"{name}_torque"] for name in others})
    out["pins"] = cycle["pins"]
    if cycle["singular_rows"]:
        out["dead_points"] = cycle["singular_rows"]
    out["rows"] = forces_rows(rows, inputs, others)
    _notes(rows, inputs, study.unit(units), mech.DEAD_POINT, notes, mech.TOGGLE)
    return out


def _listed(values, unit: str) -> str:
    shown = ", ".join(num(float(v)) for v in values[:MAX_LISTED])
    more = f" and {len(values) - MAX_LISTED} more rows" if len(values) > MAX_LISTED else ""
    return f"{shown}{more} {unit}"


def _notes(rows: LoadRows, inputs, unit: str, dead_point: str, notes: list,
           toggle_means: str = "input and coupler in line, the output stands still") -> None:
    dead = inputs[rows.singular]
    advantage = rows.mechanical_advantage
    toggle = inputs[~rows.singular & ~np.isfinite(advantage)] if advantage is not None else inputs[:0]
    if toggle.size:  # what a toggle is: the mechanism's (a drawn linkage has no "coupler")
        notes.append(f"mechanical advantage infinite (toggle: {toggle_means}) at input {_listed(toggle, unit)}")
    if dead.size:
        notes.append(f"dead point ({dead_point}): the input cannot drive the linkage, forces unbounded "
                     f"(null, left out of the load cycle) at input {_listed(dead, unit)}")

