"""Functions of the drive value tabulated once and interpolated by cubic splines: what makes the
equation of motion cheap to evaluate at every step of the integrator.

The generalized inertia, the potential and every element's coordinate are smooth functions of
the drive value q alone. They are computed exactly (the homes' closed forms, vectorized) at
N + 1 evenly spaced values over the drive's range -- a full turn (periodic splines) or, for a
drive that rocks, the part of its range away from the dead points -- and interpolated by quintic
splines, whose derivative is used as the function's. Quintic, not cubic: the integrator (of
order 8) then meets a function smooth to its fourth derivative, whose own slope is accurate to
some 1e-13 (a cubic spline's slope, to 1e-9, and its roughness, left the integration a hundred
times less accurate than its tolerance). Over a full turn the spline's collocation system is
solved by a fixed number of Jacobi passes in elementwise arithmetic, not by LAPACK: the table
has the same bits whichever BLAS the machine runs, and so does every run that reads it. A
rocking drive's range takes scipy's not-a-knot spline (make_interp_spline, k = 5): its ends
need that accuracy, and its banded solve is LAPACK's (the last bits may follow the BLAS). N doubles from 512 until the spline's error at every midpoint is below
TABLE_RTOL times the column's scale (the generalized inertia: times its own value there), up
to MAX_NODES; the equation integrated is then that of the tabulated functions, and because
M' and V' are the derivatives of the splines of M and V, it conserves their energy exactly
(tests/test_dynamics.py holds the tabulated equation against the exact one).
"""

from __future__ import annotations

import math

import numpy as np

TABLE_RTOL = 1e-13
FIRST_NODES = 512
MAX_NODES = 65536


def _basis_pieces():
    """The uniform quintic B-spline B (centred: support [-3, 3]) on the six unit intervals a
    piece sees: row m + 2 holds the coefficients (u^0 .. u^5) of B(u - m), u in [0, 1], m = -2
    .. 3, exact (fractions: the cardinal B-spline's truncated-power form, 1/5! sum_j (-1)^j
    C(6, j) (x + 3 - j)_+^5)."""
    from fractions import Fraction
    from math import comb
    rows = []
    for m in range(-2, 4):
        poly = [Fraction(0)] * 6
        for j in range(7):
            a = 3 - m - j  # (u + a)^5 is active over the whole of u in [0, 1] when a >= 0
            if a < 0:
                continue
            sign = -1 if j % 2 else 1
            for p in range(6):
                poly[p] += Fraction(sign * comb(6, j) * comb(5, p) * a ** (5 - p), 120)
        rows.append([float(c) for c in poly])
    return np.array(rows)


BASIS = _basis_pieces()  # (6 shifts, 6 powers)
JACOBI_PASSES = 440  # the collocation system's Jacobi passes: each shrinks the error by 57/63 or more


def _coefficients(values: np.ndarray, periodic: bool) -> np.ndarray:
    """The quintic B-spline coefficients c_-2 .. c_N+2 interpolating values (N + 1, K) at uniform
    nodes: (c_i-2 + 26 c_i-1 + 66 c_i + 26 c_i+1 + c_i+2) / 120 = y_i, solved by a fixed number of
    Jacobi passes in elementwise arithmetic (the same bits on every CPU; the system is diagonally
    dominant). Periodic: indices modulo N. Otherwise the coefficients beyond the ends continue
    quadratically (_ghosts)."""
    y = 120.0 * values
    if periodic:
        y = y[:-1]
        c = y / 120.0
        for _ in range(JACOBI_PASSES):
            c = (y - (np.roll(c, 2, axis=0) + 26.0 * np.roll(c, 1, axis=0)
                      + 26.0 * np.roll(c, -1, axis=0) + np.roll(c, -2, axis=0))) / 66.0
        return np.concatenate([c[-2:], c, c[:3]])
    c = y / 120.0
    for _ in range(JACOBI_PASSES):
        full = _ghosts(c)
        c = (y - (full[:-4] + 26.0 * full[1:-3] + 26.0 * full[3:-1] + full[4:])) / 66.0
    return _ghosts(c)


def _ghosts(c: np.ndarray) -> np.ndarray:
    """c with two coefficients added at each end, continued quadratically (c_-1 = 3 c_0 - 3 c_1 +
    c_2, c_-2 = 6 c_0 - 8 c_1 + 3 c_2; the same at the top): the end rows stay diagonally
    dominant (150 against 90, 63 against 57), so the Jacobi passes converge."""
    low1 = 3.0 * c[:1] - 3.0 * c[1:2] + c[2:3]
    low2 = 6.0 * c[:1] - 8.0 * c[1:2] + 3.0 * c[2:3]
    high1 = 3.0 * c[-1:] - 3.0 * c[-2:-1] + c[-3:-2]
    high2 = 6.0 * c[-1:] - 8.0 * c[-2:-1] + 3.0 * c[-3:-2]
    return np.concatenate([low2, low1, c, high1, high2])


class SplineTable:
    """Columns y_k(q) at uniform nodes over [lo, hi] (periodic: y(hi) = y(lo), q taken modulo
    hi - lo) as a quintic interpolating spline, held per interval as a polynomial in u, the
    offset in the interval over its width (module docstring: built in elementwise arithmetic,
    the same bits on every CPU)."""

    def __init__(self, lo: float, hi: float, values: np.ndarray, periodic: bool) -> None:
        values = np.array(values, dtype=float)
        self.lo, self.hi, self.periodic = float(lo), float(hi), periodic
        self.intervals = values.shape[0] - 1
        self.h = (self.hi - self.lo) / self.intervals
        n = self.intervals
        if periodic:
            values[-1] = values[0]
            c = _coefficients(values, periodic)  # c_-2 .. c_N+2: index + 2
            powers = []
            for p in range(6):  # interval i's coefficient of u^p: sum over shifts m of c_i+m B_m,p
                total = np.zeros((n,) + values.shape[1:])
                for m in range(6):
                    total = total + BASIS[m, p] * c[m:m + n]
                powers.append(total)
        else:  # a rocking drive's range: not-a-knot ends (scipy; its banded solve is LAPACK's)
            from scipy.interpolate import make_interp_spline
            x = self.lo + self.h * np.arange(n + 1)
            x[-1] = self.hi
            spline = make_interp_spline(x, values, k=5, axis=0)
            left = x[:-1]
            powers = [spline(left, nu=p) * (self.h ** p / math.factorial(p)) for p in range(6)]
        self.coef = np.ascontiguousarray(np.stack(powers[::-1], axis=1))  # (n, 6, K), u^5 first
        self.pieces = n
        self._rows = None

    @property
    def rows(self) -> list:
        """The coefficients as Python floats, per interval (the scalar path reads these)."""
        if self._rows is None:
            self._rows = self.coef.tolist()
        return self._rows

    def _place(self, q: float) -> tuple[int, float]:
        x = (q - self.lo) / self.h
        if self.periodic:
            x = math.fmod(x, self.intervals)
            if x < 0.0:
                x += self.intervals
        i = int(x)
        i = 0 if i < 0 else (self.intervals - 1 if i >= self.intervals else i)
        return i, x - i

    def at(self, q: float):
        """(values, derivatives) of every column at one q, as lists of floats."""
        i, u = self._place(q)
        c0, c1, c2, c3, c4, c5 = self.rows[i]
        inv = 1.0 / self.h
        values = [((((a * u + b) * u + c) * u + d) * u + e) * u + f
                  for a, b, c, d, e, f in zip(c0, c1, c2, c3, c4, c5)]
        slopes = [((((5.0 * a * u + 4.0 * b) * u + 3.0 * c) * u + 2.0 * d) * u + e) * inv
                  for a, b, c, d, e in zip(c0, c1, c2, c3, c4)]
        return values, slopes

    def coefficients_at(self, q: float):
        """(the interval's coefficients (6, K) array, the offset u in it) at one q."""
        i, u = self._place(q)
        return self.coef[i], u

    def many(self, q):
        """(values (n, K), derivatives (n, K)) at the values q (n,)."""
        x = (np.asarray(q, dtype=float) - self.lo) / self.h
        if self.periodic:
            x = np.mod(x, self.intervals)
        i = np.clip(x.astype(int), 0, self.intervals - 1)
        u = (x - i)[:, None]
        c = self.coef[i]
        values = ((((c[:, 0] * u + c[:, 1]) * u + c[:, 2]) * u + c[:, 3]) * u + c[:, 4]) * u + c[:, 5]
        slopes = (((((5.0 * c[:, 0] * u + 4.0 * c[:, 1]) * u + 3.0 * c[:, 2]) * u + 2.0 * c[:, 3]) * u
                   + c[:, 4]) / self.h)
        return values, slopes


def evaluate(c, u):
    """Values of an interval's coefficients (6, K) at its offset u (numpy)."""
    return ((((c[0] * u + c[1]) * u + c[2]) * u + c[3]) * u + c[4]) * u + c[5]


def nodes(lo: float, hi: float, intervals: int) -> np.ndarray:
    q = lo + (hi - lo) / intervals * np.arange(intervals + 1)
    q[-1] = hi
    return q


def refined(evaluate, lo: float, hi: float, periodic: bool, relative: tuple[int, ...] = (),
            skip: tuple[int, ...] = ()):
    """The SplineTable of `evaluate(q) -> (n, K)` over [lo, hi], with nodes doubled until every
    midpoint is within TABLE_RTOL of its column's scale (columns in `relative`: of their own
    value there; columns in `skip` are not judged) or MAX_NODES is reached; (table, intervals,
    achieved error)."""
    intervals = FIRST_NODES
    values = evaluate(nodes(lo, hi, intervals))
    while True:
        table = SplineTable(lo, hi, values, periodic)
        grid = nodes(lo, hi, intervals)
        middle = 0.5 * (grid[:-1] + grid[1:])
        exact = evaluate(middle)
        guess, _ = table.many(middle)
        scale = np.maximum(np.max(np.abs(values), axis=0), np.ptp(values, axis=0))
        scale = np.where(scale > 0, scale, 1.0)
        error = np.abs(guess - exact) / scale
        for k in relative:
            error[:, k] = np.abs(guess[:, k] - exact[:, k]) / np.maximum(np.abs(exact[:, k]), 1e-300)
        for k in skip:
            error[:, k] = 0.0
        worst = float(np.max(error)) if error.size else 0.0
        if worst <= TABLE_RTOL or intervals >= MAX_NODES:
            return table, intervals, worst
        both = np.empty((2 * intervals + 1, values.shape[1]))
        both[0::2] = values
        both[1::2] = exact
        values = both
        intervals *= 2
