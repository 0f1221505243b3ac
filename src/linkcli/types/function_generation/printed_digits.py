"""Do the printed digits of an optimum hold? An optimum on a constraint (the crank-rocker's
135 deg transmission limit) is feasible at full precision, but its lengths rounded to the
printed 6 digits and entered again as fixed lengths may violate that constraint by more
than the solver's feasibility tolerance (0.0003 deg for problems/crank_rocker.toml).

Rule (docs/format.md, "Printed digits of an optimum"): the free values (lengths in the length unit, start angles
in the angle unit) rounded to D significant digits, D = 1 .. 17, are evaluated again on
the design's branch. When the rounding to DEFAULT_DIGITS (the default --precision) violates
a constraint by more than FEASIBLE (the solver's own feasibility tolerance), a note says so,
with the violation, and names the fewest D from which every rounding meets every
constraint.
"""

from __future__ import annotations

import numpy as np

DEFAULT_DIGITS = 6  # the default --precision
MAX_DIGITS = 17


def rounded(values: np.ndarray, digits: np.ndarray) -> np.ndarray:
    """Each value rounded to `digits` significant digits (the %g rounding of the writers)."""
    out = np.empty((len(digits), len(values)))
    for row, dig in enumerate(digits):  # 17 rows of a few values: formatting, not a hot path
        out[row] = [float(f"{x:.{int(dig)}g}") for x in values]
    return out


def digits_note(problem, model, v: np.ndarray, sign: float, feasible: float, describe) -> str | None:
    """The note for a design whose 6-digit rounding violates a constraint, or None.
    `v`: the design values (1, n); `describe(viol, det)`: phrases of the violations."""
    if model.n_variables == 0:
        return None
    u = problem.meta.units
    is_angle = np.array([name not in problem.bounds for name in model.variables])
    shown = np.where(is_angle, u.from_rad(v[0]), v[0])  # the numbers a reader copies
    digits = np.arange(1, MAX_DIGITS + 1)
    back = rounded(shown, digits)
    per_unit = u.to_rad(1.0)  # radians per angle unit
    back = np.where(is_angle[None, :], back * per_unit, back)
    batch, det = model.evaluate(back, sign, detail=True)
    holds = np.max(batch.violation, axis=1) <= feasible
    if holds[DEFAULT_DIGITS - 1]:
        return None
    failing = np.flatnonzero(~holds)
    needed = int(digits[failing[-1]]) + 1
    k = DEFAULT_DIGITS - 1
    one = {key: (val[k:k + 1] if not isinstance(val, tuple) else tuple(x[k:k + 1] for x in val))
           for key, val in det.items()}
    what = "; ".join(describe(batch.violation[k], one)) or "a constraint is violated"
    tail = (f"it holds from {needed} significant digits (--precision {needed})" if needed <= MAX_DIGITS
            else "no rounding to 17 digits holds")
    return (f"the design rounded to the {DEFAULT_DIGITS} printed digits and entered again does not "
            f"re-check ({what}); {tail}")
