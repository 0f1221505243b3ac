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


def forces_rows(rows: LoadRows, inputs, others: dict | None = None) -> list[dict]:
    """`forces.rows`: per row input (and each other drive's angle, `others`: name -> printed
    angles), input_torque (and `<name>_torque` of each other drive), pins {name: {x, y,
    magnitude}}, mechanical_advantage (when the home has one); None where the row is singular
    (forces) or a toggle (MA)."""
    def column(values, scale=None):
        values = values if scale is None else _snap(values, scale)
        return [v if math.isfinite(v) else None for v in np.asarray(values).tolist()]
    others = others or {}
    torque = column(rows.input_torque, rows.torque_scale)
    more = {name: (column(others[name]), column(t, rows.torque_scale))
            for name, (_, t) in rows.other_drives.items()}
    advantage = None if rows.mechanical_advantage is None else column(rows.mechanical_advantage)
    pins = {name: (column(rows.pins[name][:, 0], rows.force_scale),
                   column(rows.pins[name][:, 1], rows.force_scale),
                   column(rows.magnitude(name), rows.force_scale)) for name in rows.pin_names}
    out = []
    for k, angle in enumerate(np.asarray(inputs, dtype=float).tolist()):
        row = {"input": angle}
        row.update({name: shown[k] for name, (shown, _) in more.items()})
        row["input_torque"] = torque[k]
        row.update({f"{name}_torque": t[k] for name, (_, t) in more.items()})
        row["pins"] = {name: {"x": x[k], "y": y[k], "magnitude": size[k]} for name, (x, y, size) in pins.items()}
        if advantage is not None:
            row["mechanical_advantage"] = advantage[k]
        out.append(row)
    return out


def _cycle(values, scale) -> dict:
    if values.size == 0:
        return {"max": None, "min": None, "mean": None, "amplitude": None}
    high, low = float(values.max()), float(values.min())
    snapped = _snap([high, low, values.mean(), (high - low) / 2], scale)
    return dict(zip(("max", "min", "mean", "amplitude"), map(float, snapped)))


def load_cycle(rows: LoadRows, inputs, others: dict | None = None) -> dict:
    """The load cycle over the valid (non-singular) rows, for a fatigue check.

    pins: per pin max, min, mean, amplitude (half the range) of the magnitude, and the same
    for x and y; input_torque: peak (the signed torque of largest magnitude; ties within a
    relative linkcli.noise.TIE go to the first row in sweep order), at_input (its input), rms;
    the same for each other drive's torque (`<name>_torque`), each summary also naming the
    other drives' angles at its peak (`at_<name>`; `others`: name -> printed angles);
    singular_rows: how many rows are dead points (left out; their loads are unbounded).
    """
    inputs = np.asarray(inputs, dtype=float)
    others = others or {}
    valid = ~rows.singular
    pins = {}
    for name in rows.pin_names:
        xy = rows.pins[name][valid]
        pins[name] = _cycle(np.hypot(xy[:, 0], xy[:, 1]), rows.force_scale)
        pins[name]["x"] = _cycle(xy[:, 0], rows.force_scale)
        pins[name]["y"] = _cycle(xy[:, 1], rows.force_scale)
    out = {"pins": pins, "input_torque": _peak(rows.input_torque, valid, inputs, others, rows.torque_scale)}
    for name, (_, torque) in rows.other_drives.items():
        out[f"{name}_torque"] = _peak(torque, valid, inputs, others, rows.torque_scale)
    out["singular_rows"] = int(np.sum(rows.singular))
    return out


def _peak(torque, valid, inputs, others: dict, scale) -> dict:
    """peak, at_input (and at_<name> of the other drives), rms of a drive's torque over the valid
    rows."""
    torque = np.asarray(torque, dtype=float)[valid]
    if not torque.size:
        return {"peak": None, "at_input": None, **{f"at_{k}": None for k in others}, "rms": None}
    first = int(first_max(np.abs(torque)))
    rms = np.sqrt(np.mean(torque ** 2))
    return {"peak": float(_snap(torque[first], scale)), "at_input": float(inputs[valid][first]),
            **{f"at_{k}": float(np.asarray(v, dtype=float)[valid][first]) for k, v in others.items()},
            "rms": float(_snap(rms, scale))}
