"""What a slider-crank precision-position file decides before any solve, in pure Python
(so that `linkcli check` refuses what `synth` refuses, without importing numpy).

The pin B = (s, e) lies at rod length b from the crank pin A = a e^{i phi}, which is linear
in x1 = 2a, x2 = 2ae, x3 = a^2 + e^2 - b^2 (slider_synthesis.py derives it):

    x1 s cos(phi) + x2 sin(phi) - x3 = s^2,   a = x1 / 2, e = x2 / x1, b^2 = a^2 + e^2 - x3,

one row [s cos phi, sin phi, -1] per position, s divided by the largest |s| (scale-free).
The positions determine no slider-crank when every s is 0, when the system is singular (its
2-norm condition number, one-sided Jacobi as for Freudenstein's system, above 1e12), when
its least-squares solution (Householder QR) gives an infinite or a zero crank, or when no
real rod joins them: b^2 <= 0 for three positions; for more, b^2 <= 0 and no three of them
(the SUBSET_STARTS triples the solver starts from) give a real rod either.
"""

from __future__ import annotations

import itertools
import math

from linkcli.types.precision_position.system import ILL_CONDITIONED, condition_number

ZERO_CRANK = 1e-12  # |a| at or below this (times the largest |s|): no crank
INFINITE_CRANK = 1e12  # |a| above this (times the largest |s|): no finite crank
SINGULAR_TRIPLE = 1e-12  # |det| of a triple's 3 x 3 system at or below: no start from it
SUBSET_STARTS = 20  # triples of positions tried as starts when there are more than three


def slider_rows(phi, sn) -> tuple[list[list[float]], list[float]]:
    """Rows [s cos phi, sin phi, -1] and right-hand sides s^2 (s already scaled)."""
    return ([[s * math.cos(p), math.sin(p), -1.0] for p, s in zip(phi, sn)], [s * s for s in sn])


def least_squares(rows: list[list[float]], rhs: list[float]) -> list[float]:
    """x minimizing |rows x - rhs| for an n x 3 matrix of full rank, by Householder QR
    (Golub & Van Loan, Matrix Computations, sec. 5.3): no normal equations, whose
    condition number would be the square of the matrix's."""
    a = [list(r) + [b] for r, b in zip(rows, rhs)]  # the right-hand side rides along
    n = len(a)
    for k in range(3):
        norm = math.sqrt(math.fsum(a[i][k] ** 2 for i in range(k, n)))
        if norm == 0.0:
            continue
        alpha = -math.copysign(norm, a[k][k])
        v = [0.0] * k + [a[k][k] - alpha] + [a[i][k] for i in range(k + 1, n)]
        vv = math.fsum(x * x for x in v[k:])
        if vv == 0.0:
            continue
        for j in range(k, 4):
            f = 2.0 * math.fsum(v[i] * a[i][j] for i in range(k, n)) / vv
            for i in range(k, n):
                a[i][j] -= f * v[i]
    x = [0.0, 0.0, 0.0]
    for k in (2, 1, 0):
        x[k] = (a[k][3] - math.fsum(a[k][j] * x[j] for j in range(k + 1, 3))) / a[k][k]
    return x


def crank_rod_offset(x: list[float]) -> tuple[float, float, float]:
    """(a signed, b^2, e) from x = (2a, 2ae, a^2 + e^2 - b^2); inf/nan for x1 = 0."""
    a = x[0] / 2.0
    e = x[1] / x[0] if x[0] != 0.0 else math.copysign(math.inf, x[1]) if x[1] else math.nan
    return a, a * a + e * e - x[2], e


def subset_combinations(n: int) -> list[tuple[int, int, int]]:
    """The triples of positions the least-squares fit starts from: all of them up to
    SUBSET_STARTS, else SUBSET_STARTS spread evenly over their lexicographic order."""
    combos = list(itertools.combinations(range(n), 3))
    if len(combos) <= SUBSET_STARTS:
        return combos
    last = len(combos) - 1
    return [combos[(last * k) // (SUBSET_STARTS - 1)] for k in range(SUBSET_STARTS)]


def _det(m: list[list[float]]) -> float:
    return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))


def _triple_has_real_rod(rows, rhs, triple) -> bool:
    """The exact slider-crank through three of the positions (Cramer's rule) has a finite,
    nonzero crank and a real rod."""
    m = [rows[i] for i in triple]
    whole = _det(m)
    if not abs(whole) > SINGULAR_TRIPLE:
        return False
    x = [_det([[rhs[i] if k == j else m[r][k] for k in range(3)] for r, i in enumerate(triple)]) / whole
         for j in range(3)]
    a, b2, e = crank_rod_offset(x)
    return math.isfinite(a) and math.isfinite(e) and abs(a) > ZERO_CRANK and b2 > 0


def slider_position_problem(phi, s) -> tuple[str, str] | None:
    """(expected, found) of the first reason the (crank angle rad, slider position) pairs
    determine no slider-crank, or None (module docstring). The pairs are finite, at least
    three, at distinct angles (checked when read)."""
    n = len(phi)
    every = "positions " + ", ".join(str(i + 1) for i in range(n))
    scale = max(abs(v) for v in s)
    if scale == 0.0:
        return "positions that determine a slider-crank", f"{every} all at s = 0"
    rows, rhs = slider_rows(phi, [v / scale for v in s])
    if condition_number(rows) > ILL_CONDITIONED:
        return ("positions that determine a slider-crank (the linear system is singular)",
                f"{every} give a singular system")
    a, b2, e = crank_rod_offset(least_squares(rows, rhs))
    if abs(a) <= ZERO_CRANK:  # (its offset x2 / x1 is then undefined, not infinite)
        return "positions that determine a crank of nonzero length", f"{every} give a zero crank"
    if not (math.isfinite(a) and math.isfinite(e)) or abs(a) > INFINITE_CRANK:
        return "positions that determine a finite crank", f"{every} give an infinite crank"
    if b2 > 0:
        return None
    if n == 3:
        return ("positions that a real rod can join",
                f"{every} need coupler^2 = {b2 * scale * scale:.6g} <= 0")
    if any(_triple_has_real_rod(rows, rhs, t) for t in subset_combinations(n)):
        return None
    return ("positions that a real rod can join",
            f"{every} need coupler^2 = {b2 * scale * scale:.6g} <= 0, and no three of them give "
            "a real rod")
