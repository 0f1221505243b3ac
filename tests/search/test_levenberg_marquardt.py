"""The batched, boxed Levenberg-Marquardt against closed-form optima.

Rosenbrock's valley as least squares, r = (10 (y - x^2), 1 - x), minimum at (1, 1), from
the classic start (-1.2, 1) and others at once; the same inside a box that cuts the
minimum off (x <= 0.5: the constrained minimum is on the bound at x = 0.5, y = 0.25, where
the first residual vanishes); Jacobians in closed form."""

from __future__ import annotations

import numpy as np

from linkcli.search.budget import Budget
from linkcli.search.levenberg_marquardt import batch_lm


class Rosenbrock:
    def __init__(self, lo, hi):
        self.lo, self.hi = np.asarray(lo, float), np.asarray(hi, float)
        self.budget = Budget(10**7)

    def residuals(self, z, rows):
        self.budget.add(len(z))
        x, y = z[:, 0], z[:, 1]
        return np.stack([10.0 * (y - x * x), 1.0 - x], axis=1)

    def jacobian(self, z, rows, r0):
        self.budget.add(len(z))
        x = z[:, 0]
        jac = np.zeros((len(z), 2, 2))
        jac[:, 0, 0], jac[:, 0, 1], jac[:, 1, 0] = -20.0 * x, 10.0, -1.0
        return jac


STARTS = np.array([[-1.2, 1.0], [2.0, -1.0], [-0.5, 3.0], [0.0, 0.0]])


def test_rosenbrock_valley_reaches_its_minimum_from_every_start():
    z, f, done = batch_lm(Rosenbrock([-5, -5], [5, 5]), STARTS, 200)
    assert np.all(done)
    assert np.allclose(z, 1.0, atol=1e-8)
    assert np.all(f < 1e-20)


def test_classic_start_takes_few_iterations():
    """From (-1.2, 1) the valley needs a few dozen steps, not hundreds (the crawl the
    damping rule must avoid)."""
    problem = Rosenbrock([-5, -5], [5, 5])
    z, f, done = batch_lm(problem, STARTS[:1], 60)
    assert done[0] and np.allclose(z[0], 1.0, atol=1e-8)


def test_a_bound_that_cuts_off_the_minimum_holds_it():
    z, f, done = batch_lm(Rosenbrock([-5, -5], [0.5, 5]), STARTS, 300)
    assert np.allclose(z[:, 0], 0.5, atol=1e-12)
    assert np.allclose(z[:, 1], 0.25, atol=1e-8)
    assert np.allclose(f, 0.25, rtol=1e-10)  # (1 - 0.5)^2


class Plane:
    """r = z - t with the linear constraint sum(z) <= b held by the LM (`linear`): the
    minimum is t's projection on the plane, t - (sum t - b) / k, where that is inside the
    box; with z_0 >= 0.5 binding too, z_0 = 0.5 and the rest t_i - mu with
    mu = (sum of the rest of t - (b - 0.5)) / (k - 1) (the KKT conditions)."""

    def __init__(self, t, b, lo, hi):
        self.t = np.asarray(t, float)
        self.lo, self.hi = np.asarray(lo, float), np.asarray(hi, float)
        self.linear = (np.ones(len(self.t)), float(b))
        self.budget = Budget(10**7)

    def residuals(self, z, rows):
        self.budget.add(len(z))
        return z - self.t[None, :]

    def jacobian(self, z, rows, r0):
        return np.repeat(np.eye(len(self.t))[None], len(z), axis=0)


PLANE_STARTS = np.array([[0.0, 0.0, 0.0, 0.0], [5.0, 5.0, 5.0, 5.0], [-3.0, 1.0, 4.0, -2.0]])


def test_a_linear_constraint_is_held_on_its_plane():
    z, f, done = batch_lm(Plane([1, 2, 3, 4], 6.0, [-10] * 4, [10] * 4), PLANE_STARTS, 100)
    assert np.all(done)
    assert np.allclose(z, [0.0, 1.0, 2.0, 3.0], atol=1e-10)  # t - (10 - 6) / 4
    assert np.allclose(f, 4.0, rtol=1e-10)


def test_a_linear_constraint_and_a_bound_both_binding():
    z, f, done = batch_lm(Plane([1, 2, 3, 4], 6.0, [0.5, -10, -10, -10], [10] * 4), PLANE_STARTS, 100)
    mu = (2 + 3 + 4 - (6 - 0.5)) / 3
    assert np.allclose(z, [0.5, 2 - mu, 3 - mu, 4 - mu], atol=1e-10)
    assert np.allclose(z.sum(axis=1), 6.0, atol=1e-10)


def test_an_inactive_linear_constraint_changes_nothing():
    z, f, done = batch_lm(Plane([1, 2, 3, 4], 20.0, [-10] * 4, [10] * 4), PLANE_STARTS, 100)
    assert np.allclose(z, [1, 2, 3, 4], atol=1e-12) and np.all(f < 1e-24)


class SteepRosenbrock(Rosenbrock):
    """r = (1000 (y - x^2), 1 - x): the same minimum (1, 1) at the end of a valley a
    hundred times narrower, where plain steps follow its tangent and crawl."""

    def residuals(self, z, rows):
        self.budget.add(len(z))
        x, y = z[:, 0], z[:, 1]
        return np.stack([1000.0 * (y - x * x), 1.0 - x], axis=1)

    def jacobian(self, z, rows, r0):
        jac = super().jacobian(z, rows, r0)
        return jac * np.array([[100.0], [1.0]])  # the first row's slopes, 100 times steeper


def test_geodesic_acceleration_follows_a_narrow_curved_valley():
    """Transtrum & Sethna's acceleration bends the step along the valley: 150 steps reach
    the minimum from three classic starts, where the plain steps are still on their way."""
    starts = np.array([[-1.2, 1.0], [2.0, -1.0], [0.0, 0.0]])
    z, f, done = batch_lm(SteepRosenbrock([-5, -5], [5, 5]), starts, 150, acceleration=True)
    assert np.allclose(z, 1.0, atol=1e-8) and np.all(done)
    plain, _, _ = batch_lm(SteepRosenbrock([-5, -5], [5, 5]), starts, 150)
    assert np.all(np.abs(plain - 1.0).max(axis=1) > 1e-3)


def test_geodesic_acceleration_keeps_the_box():
    z, f, done = batch_lm(SteepRosenbrock([-5, -5], [0.5, 5]), STARTS, 300, acceleration=True)
    assert np.allclose(z[:, 0], 0.5, atol=1e-12)
    assert np.allclose(z[:, 1], 0.25, atol=1e-8)
