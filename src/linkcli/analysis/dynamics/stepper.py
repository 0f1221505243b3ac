"""scipy's DOP853 with its sums made independent of the machine's BLAS.

scipy.integrate.DOP853 combines its stages with numpy.dot, which hands small matrix-vector
products to the BLAS; each OpenBLAS kernel (chosen by CPU) rounds them differently in the last
bit, and the step-size control turns last bits into different step sequences: a run's printed
digits then followed the machine. This subclass takes the same steps, error estimate and dense
output (Hairer, Norsett & Wanner, Solving Ordinary Differential Equations I, sec. II.10; scipy's
coefficients) with every stage combination written as an elementwise product summed row by row
(numpy's elementwise arithmetic rounds the same on every CPU), so that a run repeats its bits
wherever its right-hand side does. It is passed to scipy.integrate.solve_ivp as its method.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import DOP853
from scipy.integrate._ivp import dop853_coefficients
from scipy.integrate._ivp.rk import MAX_FACTOR, MIN_FACTOR, SAFETY, Dop853DenseOutput


def combine(rows: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """sum_i weights[i] rows[i], row by row (module docstring)."""
    return np.add.reduce(rows * weights[:, None], axis=0)


def square_sum(values: np.ndarray) -> float:
    total = 0.0
    for v in values.tolist():
        total += v * v
    return total


class SteadyDOP853(DOP853):
    """DOP853 whose arithmetic is the same on every CPU (module docstring)."""

    def _rk_step(self, t, y, f, h):
        K = self.K
        K[0] = f
        for s, (a, c) in enumerate(zip(self.A[1:], self.C[1:]), start=1):
            K[s] = self.fun(t + c * h, y + combine(K[:s], a[:s]) * h)
        y_new = y + h * combine(K[:-1], self.B)
        f_new = self.fun(t + h, y_new)
        K[-1] = f_new
        return y_new, f_new

    def _estimate_error_norm(self, K, h, scale):
        err5 = combine(K, self.E5) / scale
        err3 = combine(K, self.E3) / scale
        err5_norm_2 = square_sum(err5)
        err3_norm_2 = square_sum(err3)
        if err5_norm_2 == 0 and err3_norm_2 == 0:
            return 0.0
        denom = err5_norm_2 + 0.01 * err3_norm_2
        return abs(h) * err5_norm_2 / np.sqrt(denom * len(scale))

    def _step_impl(self):
        t, y = self.t, self.y
        min_step = 10 * np.abs(np.nextafter(t, self.direction * np.inf) - t)
        h_abs = min(max(self.h_abs, min_step), self.max_step)
        step_accepted = step_rejected = False
        while not step_accepted:
            if h_abs < min_step:
                return False, self.TOO_SMALL_STEP
            h = h_abs * self.direction
            t_new = t + h
            if self.direction * (t_new - self.t_bound) > 0:
                t_new = self.t_bound
            h = t_new - t
            h_abs = np.abs(h)
            y_new, f_new = self._rk_step(t, y, self.f, h)
            scale = self.atol + np.maximum(np.abs(y), np.abs(y_new)) * self.rtol
            error_norm = self._estimate_error_norm(self.K, h, scale)
            if error_norm < 1:
                factor = MAX_FACTOR if error_norm == 0 else min(MAX_FACTOR, SAFETY * error_norm ** self.error_exponent)
                if step_rejected:
                    factor = min(1, factor)
                h_abs *= factor
                step_accepted = True
            else:
                h_abs *= max(MIN_FACTOR, SAFETY * error_norm ** self.error_exponent)
                step_rejected = True
        self.h_previous = h
        self.y_old = y
        self.t = t_new
        self.y = y_new
        self.h_abs = h_abs
        self.f = f_new
        return True, None

    def _dense_output_impl(self):
        K = self.K_extended
        h = self.h_previous
        for s, (a, c) in enumerate(zip(self.A_EXTRA, self.C_EXTRA), start=self.n_stages + 1):
            K[s] = self.fun(self.t_old + c * h, self.y_old + combine(K[:s], a[:s]) * h)
        F = np.empty((dop853_coefficients.INTERPOLATOR_POWER, self.n), dtype=self.y_old.dtype)
        f_old = K[0]
        delta_y = self.y - self.y_old
        F[0] = delta_y
        F[1] = h * f_old - delta_y
        F[2] = 2 * delta_y - h * (self.f + f_old)
        for row, weights in enumerate(self.D, start=3):
            F[row] = h * combine(K, weights)
        return Dop853DenseOutput(self.t_old, self.t, self.y_old, F)


def first_step(fun, t0: float, y0, t_bound: float, rtol: float, atol, order: int = 7) -> float:
    """scipy's starting step (Hairer, Norsett & Wanner, sec. II.4: scipy.integrate's
    select_initial_step) with its norms summed in Python: the same on every CPU."""
    y0 = np.asarray(y0, dtype=float)
    span = abs(t_bound - t0)
    if span == 0.0:
        return 0.0

    def norm(x):
        return float(np.sqrt(square_sum(x) / len(x)))

    f0 = np.asarray(fun(t0, y0), dtype=float)
    scale = atol + np.abs(y0) * rtol
    d0, d1 = norm(y0 / scale), norm(f0 / scale)
    h0 = 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1
    h0 = min(h0, span)
    f1 = np.asarray(fun(t0 + h0, y0 + h0 * f0), dtype=float)
    d2 = norm((f1 - f0) / scale) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1 / (order + 1))
    return min(100 * h0, h1, span)
