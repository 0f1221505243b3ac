"""Arrow-shaped Jacobians (linkcli.search.arrow): J^T r, diag(J^T J) and the damped normal
equations solved by block elimination, against the dense matrices assembled here and
numpy.linalg (an independent solver); and the Levenberg-Marquardt on an arrow problem
against the same problem with dense Jacobians."""

from __future__ import annotations

import numpy as np
import pytest

from linkcli.search.arrow import Arrow
from linkcli.search.budget import Budget
from linkcli.search.levenberg_marquardt import batch_lm


def random_arrow(rng, rows=3, p=4, n=7, per=3, extra=2):
    """An Arrow with `per` rows for each of n angles in shuffled order, `extra` rows no
    angle moves, and its dense (rows, m, p + n) twin."""
    owner = np.concatenate([np.repeat(np.arange(n), per), np.full(extra, -1)])
    owner = owner[rng.permutation(len(owner))]
    m = len(owner)
    dense = rng.normal(size=(rows, m, p))
    local = np.where(owner >= 0, rng.normal(size=(rows, m)), 0.0)
    full = np.zeros((rows, m, p + n))
    full[:, :, :p] = dense
    for r in range(m):
        if owner[r] >= 0:
            full[:, r, p + owner[r]] = local[:, r]
    return Arrow(dense, local, owner, n), full


def test_gradient_diagonal_and_solve_match_the_dense_system():
    rng = np.random.default_rng(1)
    arrow, full = random_arrow(rng)
    rows, m, k = full.shape
    r = rng.normal(size=(rows, m))
    keep = rng.random((rows, k)) > 0.25
    damp = rng.uniform(0.1, 2.0, (rows, k))
    y = rng.normal(size=(rows, k))
    np.testing.assert_allclose(arrow.gradient(r), np.einsum("nmk,nm->nk", full, r), rtol=1e-12, atol=1e-12)
    normal = arrow.normal(keep)
    x = normal.solve(damp, y)
    for i in range(rows):
        h = full[i].T @ full[i] * np.outer(keep[i], keep[i])
        np.testing.assert_allclose(normal.diagonal()[i], np.diag(h), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(x[i], np.linalg.solve(h + np.diag(damp[i]), y[i]), rtol=1e-9, atol=1e-12)


def test_no_leading_columns_is_a_diagonal_system():
    rng = np.random.default_rng(2)
    arrow, full = random_arrow(rng, p=0, extra=0)
    keep = np.ones((3, 7), dtype=bool)
    damp, y = np.full((3, 7), 0.5), rng.normal(size=(3, 7))
    x = arrow.normal(keep).solve(damp, y)
    for i in range(3):
        np.testing.assert_allclose(x[i], np.linalg.solve(full[i].T @ full[i] + 0.5 * np.eye(7), y[i]), rtol=1e-12)


def test_an_angle_without_rows_is_refused():
    with pytest.raises(ValueError):
        Arrow(np.zeros((1, 2, 1)), np.zeros((1, 2)), np.array([0, 2]), 3)


class Circles:
    """Fit n points on one circle (centre cx, cy and radius R shared; one angle per point):
    residuals (cx + R cos t_i - X_i, cy + R sin t_i - Y_i): an arrow (p = 3 shared
    unknowns, each angle moves its point's two rows), or dense."""

    def __init__(self, points, arrow: bool):
        self.points, self.arrow = points, arrow
        n = len(points)
        self.lo = np.array([-10.0, -10.0, 0.1] + [-10.0] * n)
        self.hi = np.array([10.0, 10.0, 10.0] + [10.0] * n)
        self.budget = Budget(10**9)

    def residuals(self, z, rows):
        cx, cy, rad, t = z[:, :1], z[:, 1:2], z[:, 2:3], z[:, 3:]
        rx = cx + rad * np.cos(t) - self.points[:, 0]
        ry = cy + rad * np.sin(t) - self.points[:, 1]
        return np.stack([rx, ry], axis=2).reshape(len(z), -1)

    def jacobian(self, z, rows, r0):
        n = len(self.points)
        rad, t = z[:, 2:3], z[:, 3:]
        dx = np.stack([np.ones_like(t), np.zeros_like(t), np.cos(t)], axis=2)  # (N, n, 3)
        dy = np.stack([np.zeros_like(t), np.ones_like(t), np.sin(t)], axis=2)
        dense = np.stack([dx, dy], axis=2).reshape(len(z), 2 * n, 3)
        local = np.stack([-rad * np.sin(t), rad * np.cos(t)], axis=2).reshape(len(z), 2 * n)
        owner = np.repeat(np.arange(n), 2)
        if self.arrow:
            return Arrow(dense, local, owner, n)
        full = np.zeros((len(z), 2 * n, 3 + n))
        full[:, :, :3] = dense
        full[:, np.arange(2 * n), 3 + owner] = local
        return full


def test_levenberg_marquardt_on_an_arrow_takes_the_dense_steps():
    """Same problem, same start: the arrow's block elimination and the dense elimination
    reach the same least-squares circle (the closed form: the points lie on a circle of
    centre (1, -2) and radius 3, so the optimum fits them exactly)."""
    rng = np.random.default_rng(3)
    t = np.sort(rng.uniform(0, 5, 40))
    points = np.stack([1 + 3 * np.cos(t), -2 + 3 * np.sin(t)], axis=1)
    z0 = np.concatenate([[0.5, -1.5, 2.0], t + rng.normal(0, 0.1, 40)])[None, :]
    out = {}
    for arrow in (True, False):
        z, f, conv = batch_lm(Circles(points, arrow), z0, 200)
        out[arrow] = z[0]
        assert conv[0] and f[0] < 1e-20
        np.testing.assert_allclose(z[0][:3], [1.0, -2.0, 3.0], rtol=1e-9)
    np.testing.assert_allclose(out[True], out[False], rtol=1e-9, atol=1e-12)
