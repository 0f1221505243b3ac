"""The path search's loop closure (four_bar.closure.frame) against the four-bar's
positions computed here point by point with the math module: the output pivot B0 at (d, 0),
the crank A = a e^{i phi}, the rocker end B the intersection of the circles |B - A| = b and
|B - B0| = c on the branch's side of the line A B0, and the coupler direction A -> B."""

from __future__ import annotations

import math

import numpy as np

from linkcli.mechanisms.four_bar.closure import frame


def positions(a, b, c, d, phi, sign):
    """(A, B, assembles) of one linkage at one input angle, by two circles' intersection."""
    ax, ay = a * math.cos(phi), a * math.sin(phi)
    dx, dy = d - ax, -ay  # A -> B0
    rho = math.hypot(dx, dy)
    if rho == 0.0 or rho > b + c or rho < abs(b - c):
        return (ax, ay), None, False
    along = (b * b - c * c + rho * rho) / (2.0 * rho)  # from A towards B0, to the chord
    half = math.sqrt(max(b * b - along * along, 0.0))
    mx, my = ax + along * dx / rho, ay + along * dy / rho
    # B0 -> B is B0 -> A turned by sign alpha (docs/format.md: sign -1 open, +1 crossed):
    # crossed, B lies left of the ray B0 -> A, i.e. right of A -> B0; open, the other side
    nx, ny = dy / rho, -dx / rho  # the unit normal to the right of A -> B0
    side = 1.0 if sign > 0 else -1.0
    return (ax, ay), (mx + side * half * nx, my + side * half * ny), True


def test_frame_matches_two_circles_on_both_branches():
    rng = np.random.default_rng(7)
    n, m = 40, 64
    a, b, c, d = (rng.uniform(0.3, 3.0, (n, 1)) for _ in range(4))
    sign = np.where(rng.random((n, 1)) < 0.5, -1.0, 1.0)
    phi = rng.uniform(-math.pi, math.pi, (1, m))
    out = frame(a, b, c, d, phi, sign)
    checked = 0
    for i in range(n):
        for j in range(m):
            (ax, ay), bpt, ok = positions(a[i, 0], b[i, 0], c[i, 0], d[i, 0], phi[0, j], sign[i, 0])
            assert bool(out.valid[i, j]) == ok or abs(out.rho[i, j] - (b[i, 0] + c[i, 0])) < 1e-9 \
                or abs(out.rho[i, j] - abs(b[i, 0] - c[i, 0])) < 1e-9
            assert math.isclose(out.cphi[i, j], math.cos(phi[0, j]), abs_tol=1e-15)
            assert math.isclose(out.rho[i, j], math.hypot(d[i, 0] - ax, ay), rel_tol=1e-15)
            if not ok:
                continue
            bx, by = bpt
            length = math.hypot(bx - ax, by - ay)
            assert abs(out.ct[i, j] - (bx - ax) / length) <= 1e-12
            assert abs(out.st[i, j] - (by - ay) / length) <= 1e-12
            assert abs(out.cpsi[i, j] - (bx - d[i, 0]) / c[i, 0]) <= 1e-12
            assert abs(out.spsi[i, j] - by / c[i, 0]) <= 1e-12
            checked += 1
    assert checked > n * m // 4  # enough assembled points were compared


def test_frame_at_a_toggle_and_where_it_cannot_assemble():
    # rho = b + c exactly (a = 1, d = 3, phi = 0: rho = 2 = 1 + 1): the toggle, B on the line
    out = frame(np.array([1.0]), np.array([1.0]), np.array([1.0]), np.array([3.0]), np.array([0.0, math.pi]), -1.0)
    assert out.valid[0]
    assert abs(out.ct[0] - 1.0) <= 1e-15 and abs(out.st[0]) <= 1e-7
    assert not out.valid[1]  # rho = 4 > b + c: clipped to the nearest toggle, not valid
    assert np.all(np.isfinite([out.ct, out.st, out.cpsi, out.spsi]))
    # A on B0 (a = d, phi = 0): rho = 0, no direction to B0: not valid, finite
    out = frame(np.array([2.0]), np.array([1.0]), np.array([1.0]), np.array([2.0]), np.array([0.0]), 1.0)
    assert not out.valid[0] and np.all(np.isfinite([out.ct, out.st, out.cpsi, out.spsi]))
