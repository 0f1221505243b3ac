"""Functions of the drive value tabulated once and interpolated by cubic splines: what makes the
equation of motion cheap to evaluate at every step of the integrator.

The generalized inertia, the potential and every element's coordinate are smooth functions of
the drive value q alone. They are computed exactly (the homes' closed forms, vectorized) at
N + 1 evenly spaced values over the drive's range -- a full turn (periodic splines) or, for a
drive that rocks, the part of its range away from the dead points -- and interpolated by cubic
splines (scipy.interpolate.CubicSpline: periodic, or not-a-knot), whose derivative is used as
the function's. N doubles from 512 until the spline's error at every midpoint is below
TABLE_RTOL times the column's scale (the generalized inertia: times its own value there), up
to MAX_NODES; the equation integrated is then that of the tabulated functions, and because
M' and V' are the derivatives of the splines of M and V, it conserves their energy exactly
(tests/test_dynamics.py holds the tabulated equation against the exact one).
"""

from __future__ import annotations

import math

import numpy as np

TABLE_RTOL = 1e-11
FIRST_NODES = 512
MAX_NODES = 65536


class SplineTable:
    """Columns y_k(q) at uniform nodes over [lo, hi] (periodic: y(hi) = y(lo), q taken modulo
    hi - lo), as cubic spline coefficients per interval."""

    def __init__(self, lo: float, hi: float, values: np.ndarray, periodic: bool) -> None:
        from scipy.interpolate import CubicSpline
        values = np.array(values, dtype=float)
        nodes = values.shape[0]
        self.lo, self.hi, self.periodic = float(lo), float(hi), periodic
        self.intervals = nodes - 1
        self.h = (self.hi - self.lo) / self.intervals
        x = self.lo + self.h * np.arange(nodes)
        x[-1] = self.hi
        if periodic:
            values[-1] = values[0]
        spline = CubicSpline(x, values, axis=0, bc_type="periodic" if periodic else "not-a-knot")
        self.coef = np.ascontiguousarray(np.moveaxis(spline.c, 0, 1))  # (intervals, 4, K)
        self._rows = None

    @property
    def rows(self) -> list:
        """The coefficients as Python floats, per interval (the scalar path reads these)."""
        if self._rows is None:
            self._rows = self.coef.tolist()
        return self._rows

    def _place(self, q: float) -> tuple[int, float]:
        x = q - self.lo
        if self.periodic:
            x = math.fmod(x, self.hi - self.lo)
            if x < 0.0:
                x += self.hi - self.lo
        i = int(x / self.h)
        i = 0 if i < 0 else (self.intervals - 1 if i >= self.intervals else i)
        return i, x - i * self.h

    def at(self, q: float):
        """(values, derivatives) of every column at one q, as lists of floats."""
        i, t = self._place(q)
        c0, c1, c2, c3 = self.rows[i]
        values = [((a * t + b) * t + c) * t + d for a, b, c, d in zip(c0, c1, c2, c3)]
        slopes = [(3.0 * a * t + 2.0 * b) * t + c for a, b, c in zip(c0, c1, c2)]
        return values, slopes

    def many(self, q):
        """(values (n, K), derivatives (n, K)) at the values q (n,)."""
        q = np.asarray(q, dtype=float)
        x = q - self.lo
        if self.periodic:
            x = np.mod(x, self.hi - self.lo)
        i = np.clip((x / self.h).astype(int), 0, self.intervals - 1)
        t = (x - i * self.h)[:, None]
        c = self.coef[i]
        values = ((c[:, 0] * t + c[:, 1]) * t + c[:, 2]) * t + c[:, 3]
        slopes = (3.0 * c[:, 0] * t + 2.0 * c[:, 1]) * t + c[:, 2]
        return values, slopes


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
