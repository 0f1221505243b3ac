"""ISO 2768-1 general tolerances for linear dimensions, as data (docs/tolerance.md).

Source: ISO 2768-1:1989 "General tolerances -- Part 1: Tolerances for linear and angular
dimensions without individual tolerance indications", Table 1 (permissible deviations for
linear dimensions except broken edges). Classes f (fine), m (medium), c (coarse), v (very
coarse); ranges of nominal size "from 0.5 up to 3" mm, then "over lo up to hi" to 4000 mm.
Below 0.5 mm the standard gives no general tolerance (the deviation is written beside the
size), nor does class v up to 3 mm or class f over 2000 mm.
"""

from __future__ import annotations

import re

CLASSES = ("f", "m", "c", "v")
NAME = re.compile(r"ISO 2768-([fmcv])")
LOWEST = 0.5  # mm
RANGES = (3, 6, 30, 120, 400, 1000, 2000, 4000)  # upper limits, mm
DEVIATION = {  # +- mm per range; None: no general tolerance in that range
    "f": (0.05, 0.05, 0.1, 0.15, 0.2, 0.3, 0.5, None),
    "m": (0.1, 0.1, 0.2, 0.3, 0.5, 0.8, 1.2, 2.0),
    "c": (0.2, 0.3, 0.5, 0.8, 1.2, 2.0, 3.0, 4.0),
    "v": (None, 0.5, 1.0, 1.5, 2.5, 4.0, 6.0, 8.0),
}


class GeneralToleranceError(ValueError):
    """A nominal size the class has no general tolerance for; the message says which sizes do."""


def tolerance_class(text: str) -> str | None:
    """"ISO 2768-m" -> "m"; None for another text."""
    m = NAME.fullmatch(text)
    return m.group(1) if m else None


def deviation(cls: str, size: float) -> float:
    """The permissible deviation +- (mm) of class `cls` for a nominal size (mm), by its
    magnitude (a signed offset counts by its size)."""
    size = abs(size)
    row = DEVIATION[cls]
    if LOWEST <= size <= RANGES[-1]:
        value = row[next(i for i, hi in enumerate(RANGES) if size <= hi)]
        if value is not None:
            return value
    sizes = [(LOWEST if i == 0 else RANGES[i - 1], hi) for i, hi in enumerate(RANGES) if row[i] is not None]
    lo, hi = sizes[0][0], sizes[-1][1]
    raise GeneralToleranceError(f"a nominal size from {lo:g} to {hi:g} mm for ISO 2768-{cls}, found {size:.6g} mm")
