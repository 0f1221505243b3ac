"""The noise floor and the tie rule: what makes printed numbers the same on every machine.

Two machines (or two OpenBLAS kernels on one machine) round differently in the last bits of
a matrix product or a transcendental function. linkcli never lets those bits reach a printed
digit or a decision:

- **Noise floor.** A value whose magnitude is at most `NOISE_FLOOR` times the scale of the
  quantity it measures is round-off, and is reported as exactly 0: a residual of an exact fit
  (scale: 1 rad for angle errors, the problem's length scale for distances), an objective
  (scale: the number of terms times the squared error scale), a velocity or acceleration at
  rest (scale: the largest magnitude of its column, and at least the natural scale of the
  motion), an angle that is 0 up to round-off (scale: 1 rad). `snap(value, scale)`.
- **Ties.** Two values within a relative `TIE` of each other are equal, and the first in the
  documented order (sweep order for peaks, generation order for candidates) wins:
  `same(a, b)`, `first_max(values)`, `first_min(values)`.

Both constants are relative and stated in docs/determinism.md (a test reads them there). numpy
is imported by the functions that use it: a problem file's reader takes the constants, and
`check` imports no numpy.
"""

from __future__ import annotations

NOISE_FLOOR = 1e-9  # relative to the quantity's scale: below it a value is round-off
TIE = 1e-9  # relative: two values this close are equal, the first in order wins


def snap(value, scale):
    """`value` with every entry of magnitude <= NOISE_FLOOR * |scale| replaced by 0.0 (and
    -0.0 by 0.0); floats stay floats, arrays stay arrays, NaN and inf pass through."""
    import numpy as np  # here: `check` reads the constants above without numpy
    v = np.asarray(value, dtype=float)
    s = np.abs(np.asarray(scale, dtype=float))
    with np.errstate(invalid="ignore"):
        out = np.where(np.abs(v) <= NOISE_FLOOR * s, 0.0, v) + 0.0
    if np.ndim(value) == 0 and np.ndim(scale) == 0:
        return float(out)
    return out


def snap_series(values, natural_scale: float = 0.0):
    """A series (a column of a table) snapped against the larger of its own largest finite
    magnitude and `natural_scale`: entries that are round-off of the series become 0."""
    import numpy as np  # here: `check` reads the constants above without numpy
    v = np.asarray(values, dtype=float)
    finite = np.abs(v[np.isfinite(v)])
    top = float(finite.max()) if finite.size else 0.0
    return snap(v, max(top, abs(natural_scale)))


def quantize(value: float, step: float = NOISE_FLOOR) -> float:
    """`value` rounded to a whole number of `step` (default: the noise floor), for numbers
    whose absolute digits below the step are round-off, like a relative gap to a best known
    objective: a gap of 1.08268e-08 and one of 1.08266e-08 both become 1.1e-08."""
    import numpy as np  # here: `check` reads the constants above without numpy
    if not np.isfinite(value):
        return float(value)
    return float(round(value / step) * step) + 0.0


def same(a: float, b: float) -> bool:
    """a and b are equal within the tie rule: |a - b| <= TIE * max(|a|, |b|) (both inf of one
    sign are equal)."""
    if a == b:
        return True
    return bool(abs(a - b) <= TIE * max(abs(a), abs(b)))


def first_max(values, axis: int = -1):
    """Index of the largest value along `axis`, where values within a relative TIE of the
    largest count as equal and the first of them (lowest index) wins. NaN never wins."""
    import numpy as np  # here: `check` reads the constants above without numpy
    v = np.asarray(values, dtype=float)
    v = np.where(np.isnan(v), -np.inf, v)
    top = np.max(v, axis=axis, keepdims=True)
    with np.errstate(invalid="ignore"):
        near = (v >= top - TIE * np.abs(top)) | (v == top)
    return np.argmax(near, axis=axis)


def first_min(values, axis: int = -1):
    """Index of the smallest value along `axis` under the same rule as `first_max`."""
    import numpy as np  # here: `check` reads the constants above without numpy
    v = np.asarray(values, dtype=float)
    return first_max(np.where(np.isnan(v), np.nan, -v), axis=axis)
