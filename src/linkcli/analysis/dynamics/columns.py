"""The printed columns of the [dynamics] sections, one drive or several: integrated quantities
carry the integrator's error (about 1e-10 of their scale), so a value below DYNAMICS_FLOOR times
its column's scale prints as 0, and the energy balance below BALANCE_FLOOR times the energies'
scale, so that printed digits are the same on every machine.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.noise import snap

DYNAMICS_FLOOR = 1e-7
BALANCE_FLOOR = 1e-7
MAX_EVENT_ROWS = 100  # listed events; more are counted


def column(values, floor: float = DYNAMICS_FLOOR, scale: float = 0.0) -> list:
    """A column of the history: snapped against its largest finite magnitude (and `scale`);
    None where not finite."""
    v = np.asarray(values, dtype=float)
    finite = np.abs(v[np.isfinite(v)])
    top = max(float(finite.max()) if finite.size else 0.0, abs(scale))
    with np.errstate(invalid="ignore"):
        out = np.where(np.abs(v) <= floor * top, 0.0, v) + 0.0
    return [x if math.isfinite(x) else None for x in out.tolist()]


def snapped(value, scale) -> float:
    """A single value snapped against `scale` under DYNAMICS_FLOOR."""
    return float(snap(float(value), DYNAMICS_FLOOR * 1e9 * abs(float(scale))))  # noise.snap's floor is 1e-9


def with_forces(row: dict, k: int, pins: dict, elements: dict, friction: dict) -> dict:
    """A history row with row k's pin forces (x, y, magnitude), the force elements' values and
    the pins' friction couples (the last two only when there are any)."""
    row["pins"] = {name: {"x": x[k], "y": yy[k], "magnitude": size[k]} for name, (x, yy, size) in pins.items()}
    if elements:
        row["elements"] = {name: values[k] for name, values in elements.items()}
    if friction:
        row["friction"] = {name: values[k] for name, values in friction.items()}
    return row


def energy_section(kinetic_rows, potential_rows, spring_rows, drive, damper, friction) -> dict:
    """At the end: kinetic (and at the start), potential (gravity and the constant loads,
    relative to the start), spring (stored, and at the start), the work of the drive(s), the
    dampers and friction (the integrated works at the end), and their balance."""
    kinetic, kinetic0 = float(kinetic_rows[-1]), float(kinetic_rows[0])
    potential = float(potential_rows[-1] - potential_rows[0])
    spring, spring0 = float(spring_rows[-1]), float(spring_rows[0])
    drive, damper, friction = float(drive), float(damper), float(friction)
    balance = (kinetic - kinetic0) + potential + (spring - spring0) - drive - damper - friction
    scale = max(abs(kinetic), abs(kinetic0), abs(potential), abs(spring), abs(spring0), abs(drive),
                abs(damper), abs(friction), 1e-300)
    def s(v):
        return float(snap(v, DYNAMICS_FLOOR * 1e9 * scale))
    return {"kinetic": s(kinetic), "potential": s(potential), "spring": s(spring),
            "drive_work": s(drive), "damper_work": s(damper), "friction_work": s(friction),
            "balance": float(snap(balance, BALANCE_FLOOR * 1e9 * scale)),
            "start": {"kinetic": s(kinetic0), "spring": s(spring0)}}
