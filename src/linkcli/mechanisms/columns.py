"""What every home's report sections share: angles in the output unit, rows from columns,
and the recommended transmission band.

Positions leave wrapped to (-180, 180] deg in the file's angle unit, round-off of 0 (below the
noise floor of 1 rad) as 0; differences and magnitudes unwrapped.
"""

from __future__ import annotations

import numpy as np

from linkcli.angles import wrap
from linkcli.noise import snap

TRANSMISSION_BAND = (40.0, 140.0)  # deg: the usual recommendation (Norton, ch. 3)


def angle_out(units, x) -> float:
    """A position angle in the output unit, wrapped to (-180, 180] deg; round-off of 0 is 0."""
    return float(units.from_rad(snap(float(wrap(x)), 1.0)))


def turn_out(units, x) -> float:
    """An angle difference or magnitude in the output unit (no wrap)."""
    return float(units.from_rad(float(x)))


def rows_of(columns: list[tuple[str, np.ndarray]], valid) -> list[dict]:
    """One dict per row from named columns: a value that is not finite, or any value but the
    `input` in a row that does not assemble (only the input is known there), is None."""
    valid = np.asarray(valid, dtype=bool)
    names, lists = [], []
    for name, v in columns:
        v = np.asarray(v, dtype=float)
        keep = np.isfinite(v) if name == "input" else np.isfinite(v) & valid
        names.append(name)
        lists.append([x if k else None for x, k in zip(v.tolist(), keep.tolist())])
    return [dict(zip(names, values)) for values in zip(*lists)]
