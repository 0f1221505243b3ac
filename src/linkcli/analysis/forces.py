"""The `forces` section (docs/loads.md): input torque, pin forces and mechanical advantage at
the motion study's rows, from a problem's [loads] and [masses].

The rows are the kinematics section's (`sections.study_inputs`: the same input angles at the
same constant `[motion] input_speed`); the linkage's own kinematics give every row's positions,
angular velocities and accelerations, and `linkcli.analysis.loads` solves the Newton-Euler
equations of all rows in one batched solve. Dispatch on the linkage's class: a `FourBar`
(pins A0, A, B, B0) or a `SliderCrank` (pins A0, A, B and the guide's normal force).
Lengths enter in metres whatever the file's unit: torques in N m, forces in N.
"""

from __future__ import annotations

import numpy as np

from linkcli.analysis.loads import (FourBarState, LoadRows, SliderCrankState, forces_rows,
                                    four_bar_loads, load_cycle, slider_crank_loads)
from linkcli.model import LinkMass, Masses
from linkcli.noise import snap_series
from linkcli.textnum import num

MAX_LISTED = 6  # inputs named in a note; more are counted


def metres_per_unit(units) -> float:
    return units.mm_per_length / 1000.0


def in_metres(masses: Masses, scale: float) -> Masses:
    """The masses with their centres in metres (they are in the file's length unit)."""
    def one(m: LinkMass | None):
        return None if m is None else LinkMass(m.mass, (m.center[0] * scale, m.center[1] * scale), m.inertia)
    return Masses(one(masses.input), one(masses.coupler), one(masses.output))


def echo(case) -> dict:
    """`loads` and `masses` as given, for the report: `analyze` of a result reads them back."""
    return dict(case.given)


def four_bar_rows(fb, phi, speed: float, loads, masses, scale: float) -> LoadRows:
    """LoadRows of a four-bar at input angles phi (rad, local frame) turning at `speed` rad/s
    (constant: alpha_input = 0); lengths (file unit) times `scale` are metres."""
    from linkcli.mechanisms.four_bar import kinematics as kin
    a, b, c, d = fb.abcd
    p = kin.pose(a, b, c, d, phi, fb.branch)
    w3, w4 = kin.velocities(a, b, c, p, speed)
    a3, a4 = kin.accelerations(a, b, c, p, speed)
    point = None if fb.coupler_point is None else tuple(v * scale for v in fb.coupler_point)
    state = FourBarState.from_angles(
        ground_length=d * scale, input_length=a * scale, coupler_length=b * scale,
        output_length=c * scale, phi=phi, psi=p.psi, omega_input=speed, omega_coupler=w3,
        omega_output=w4, alpha_input=0.0, alpha_coupler=a3, alpha_output=a4, coupler_point=point,
        ground_pivot=tuple(v * scale for v in fb.ground_pivot), ground_angle=fb.ground_angle)
    return four_bar_loads(state, loads, in_metres(masses, scale))


def slider_crank_rows(sc, phi, speed: float, loads, masses, scale: float) -> LoadRows:
    """LoadRows of a slider-crank (linkcli.mechanisms.slider_crank.kinematics.SliderCrank) at crank
    angles phi (rad) turning at `speed` rad/s; the guide is the x axis at y = offset."""
    from linkcli.mechanisms.slider_crank import kinematics as slk
    a, b, e = sc.abe
    p = slk.pose(a, b, e, phi, sc.branch)
    _, w3 = slk.velocities(a, b, p, speed)
    _, a3 = slk.accelerations(a, b, p, speed)
    point = None if sc.coupler_point is None else tuple(v * scale for v in sc.coupler_point)
    state = SliderCrankState.from_angles(
        input_length=a * scale, coupler_length=b * scale, phi=phi, theta=p.theta,
        omega_input=speed, omega_coupler=w3, alpha_input=0.0, alpha_coupler=a3, coupler_point=point)
    return slider_crank_loads(state, loads, in_metres(masses, scale))


def slider_study(sc, near=None) -> tuple[bool, tuple[float, float] | None] | None:
    """(full turn, arc with hi >= lo) of a slider-crank's motion study, None if it never
    assembles."""
    from linkcli.mechanisms.slider_crank import kinematics as slk
    mot = slk.motion(*sc.abe, sc.branch, near=near)
    if not mot["assembles"]:
        return None
    if mot["input_full_turn"]:
        return True, None
    lo, hi = mot["input_arc"]
    return False, (lo, lo + slk.arc_sweep(lo, hi))


def study_of(linkage, motion=None, near=None) -> tuple[bool, tuple[float, float] | None] | None:
    """(full turn, arc) of the motion study whose rows the kinematics and forces sections
    share, None if the linkage never assembles: a four-bar's from its `Motion` (computed here
    when not given), a slider-crank's from its own range of motion."""
    if is_slider_crank(linkage):
        return slider_study(linkage, near)
    if motion is None:
        from linkcli.mechanisms.four_bar import kinematics as kin
        motion = kin.motion(*linkage.abcd, linkage.branch, near=near)
    return (motion.input_full_turn, motion.input_arc) if motion.assembles else None


def is_slider_crank(linkage) -> bool:
    """The linkage is a linkcli.mechanisms.slider_crank.kinematics.SliderCrank (imported only then)."""
    if type(linkage).__name__ != "SliderCrank":
        return False
    from linkcli.mechanisms.slider_crank.kinematics import SliderCrank
    return isinstance(linkage, SliderCrank)


def load_rows(linkage, phi, speed, case, units) -> LoadRows:
    """Dispatch on the linkage's class: FourBar or SliderCrank."""
    scale = metres_per_unit(units)
    if is_slider_crank(linkage):
        return slider_crank_rows(linkage, phi, speed, case.loads, case.masses, scale)
    return four_bar_rows(linkage, phi, speed, case.loads, case.masses, scale)


def section(linkage, study, speed: float, steps: int, case, units, notes: list) -> dict:
    """The `forces` section: input_torque {peak, at_input, rms}, pins {name: {max, min, mean,
    amplitude, x: {...}, y: {...}}}, rows [{input, input_torque, pins {name: {x, y,
    magnitude}}, mechanical_advantage}], at the rows of the motion study `study` = (full
    turn, arc). Notes name the toggles (infinite mechanical advantage) and dead points
    (unbounded forces, left out of the load cycle)."""
    from linkcli.analysis.sections import study_inputs
    phi, shown = study_inputs(*study, steps)
    inputs = units.from_rad(np.asarray(shown, dtype=float))
    rows = load_rows(linkage, phi, speed, case, units)
    rows = LoadRows(rows.input_torque, rows.pins, rows.singular,
                    snap_series(rows.mechanical_advantage), rows.force_scale, rows.torque_scale,
                    rows.pin_names)
    cycle = load_cycle(rows, inputs)
    out = {"input_torque": cycle["input_torque"], "pins": cycle["pins"]}
    if cycle["singular_rows"]:
        out["dead_points"] = cycle["singular_rows"]
    out["rows"] = forces_rows(rows, inputs)
    _notes(rows, inputs, units, is_slider_crank(linkage), notes)
    return out


def _listed(values, unit: str) -> str:
    shown = ", ".join(num(float(v)) for v in values[:MAX_LISTED])
    more = f" and {len(values) - MAX_LISTED} more rows" if len(values) > MAX_LISTED else ""
    return f"{shown}{more} {unit}"


def _notes(rows: LoadRows, inputs, units, slider: bool, notes: list) -> None:
    unit = units.angle
    dead = inputs[rows.singular]
    toggle = inputs[~rows.singular & ~np.isfinite(rows.mechanical_advantage)]
    if toggle.size:
        notes.append("mechanical advantage infinite (toggle: input and coupler in line, the output "
                     f"stands still) at input {_listed(toggle, unit)}")
    if dead.size:
        where = "the rod normal to the guide" if slider else "coupler and output in line"
        notes.append(f"dead point ({where}): the input cannot drive the linkage, forces unbounded "
                     f"(null, left out of the load cycle) at input {_listed(dead, unit)}")

