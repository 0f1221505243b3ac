"""The load cycle of a mechanism's pins and drive (docs/loads.md): the `forces` section's rows
and the per-pin summary a fatigue check starts from.

The forces themselves come from the mechanism's home (`Mechanism.load_rows`, one batched
Newton-Euler solve: mechanisms.newton_euler); here they are reduced and snapped: forces
below linkcli.noise.NOISE_FLOOR x force_scale (torques below it x torque_scale) are 0, and
the torque's peak ties within linkcli.noise.TIE go to the first row in sweep order
(noise.first_max).
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.mechanisms.protocol import LoadRows
from linkcli.noise import first_max, snap


def _snap(values, scale):
    """Round-off below the noise floor of `scale` -> 0 (linkcli.noise.snap), as an array."""
    return np.asarray(snap(np.asarray(values, dtype=float), float(scale)), dtype=float)


def forces_rows(rows: LoadRows, inputs) -> list[dict]:
    """`forces.rows`: per row input, input_torque, pins {name: {x, y, magnitude}},
    mechanical_advantage; None where the row is singular (forces) or a toggle (MA)."""
    def column(values, scale=None):
        values = values if scale is None else _snap(values, scale)
        return [v if math.isfinite(v) else None for v in np.asarray(values).tolist()]
    torque = column(rows.input_torque, rows.torque_scale)
    advantage = column(rows.mechanical_advantage)
    pins = {name: (column(rows.pins[name][:, 0], rows.force_scale),
                   column(rows.pins[name][:, 1], rows.force_scale),
                   column(rows.magnitude(name), rows.force_scale)) for name in rows.pin_names}
    return [{"input": angle, "input_torque": torque[k],
             "pins": {name: {"x": x[k], "y": y[k], "magnitude": size[k]}
                      for name, (x, y, size) in pins.items()},
             "mechanical_advantage": advantage[k]}
            for k, angle in enumerate(np.asarray(inputs, dtype=float).tolist())]


def _cycle(values, scale) -> dict:
    if values.size == 0:
        return {"max": None, "min": None, "mean": None, "amplitude": None}
    high, low = float(values.max()), float(values.min())
    snapped = _snap([high, low, values.mean(), (high - low) / 2], scale)
    return dict(zip(("max", "min", "mean", "amplitude"), map(float, snapped)))


def load_cycle(rows: LoadRows, inputs) -> dict:
    """The load cycle over the valid (non-singular) rows, for a fatigue check.

    pins: per pin max, min, mean, amplitude (half the range) of the magnitude, and the same
    for x and y; input_torque: peak (the signed torque of largest magnitude; ties within a
    relative linkcli.noise.TIE go to the first row in sweep order), at_input (its input), rms;
    singular_rows: how many rows are dead points (left out; their loads are unbounded).
    """
    inputs = np.asarray(inputs, dtype=float)
    valid = ~rows.singular
    pins = {}
    for name in rows.pin_names:
        xy = rows.pins[name][valid]
        pins[name] = _cycle(np.hypot(xy[:, 0], xy[:, 1]), rows.force_scale)
        pins[name]["x"] = _cycle(xy[:, 0], rows.force_scale)
        pins[name]["y"] = _cycle(xy[:, 1], rows.force_scale)
    torque = rows.input_torque[valid]
    if torque.size:
        first = int(first_max(np.abs(torque)))
        peak, at_input = torque[first], inputs[valid][first]
        rms = np.sqrt(np.mean(torque ** 2))
        summary = {"peak": float(_snap(peak, rows.torque_scale)), "at_input": float(at_input),
                   "rms": float(_snap(rms, rows.torque_scale))}
    else:
        summary = {"peak": None, "at_input": None, "rms": None}
    return {"pins": pins, "input_torque": summary, "singular_rows": int(np.sum(rows.singular))}
