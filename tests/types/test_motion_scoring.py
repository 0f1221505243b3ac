"""The many-pose search's body poses and start scores (motion_generation.assemble.body_frames,
least_squares._scored, least_squares.residuals) against references computed here point
by point with the math module: the rocker pin as two circles' intersection
(test_path_closure.positions), the body placed by the ground pivot and angle, and the
best input angle of a row for a pose by brute force over every grid angle."""

from __future__ import annotations

import math

import numpy as np
from test_path_closure import positions

from linkcli.types.motion_generation import assemble
from linkcli.types.motion_generation import least_squares as LS

PARAMS = np.array([0.1, -0.2, 0.3, 4.0, 1.2, 3.6, 2.9, 1.5, 1.1, 0.35])  # PARAM_NAMES order


def body_pose(p, phi, sign):
    """(x, y, angle) of the body of linkage p at input angle phi, or None where it does not
    assemble: A and B from two circles, the coupler frame at A along A -> B."""
    gx, gy, gang, d, a, b, c, px, py, cang = (float(v) for v in p)
    (ax, ay), bpt, ok = positions(a, b, c, d, phi, sign)
    if not ok:
        return None
    theta = math.atan2(bpt[1] - ay, bpt[0] - ax)
    lx = ax + px * math.cos(theta) - py * math.sin(theta)
    ly = ay + px * math.sin(theta) + py * math.cos(theta)
    x = gx + math.cos(gang) * lx - math.sin(gang) * ly
    y = gy + math.sin(gang) * lx + math.cos(gang) * ly
    return x, y, theta + cang + gang


def angle_between(u, v):
    """The wrapped difference u - v, |.| <= pi."""
    return math.remainder(u - v, 2.0 * math.pi)


def random_rows(rng, count):
    rows = np.tile(PARAMS, (count, 1))
    rows[:, 3:7] *= rng.uniform(0.6, 1.6, (count, 4))
    rows[:, [2, 9]] = rng.uniform(-math.pi, math.pi, (count, 2))
    rows[:, [0, 1, 7, 8]] += rng.normal(0.0, 0.5, (count, 4))
    return rows


def test_body_frames_place_the_body_as_two_circles_do():
    rng = np.random.default_rng(3)
    rows = random_rows(rng, 30)
    phi = rng.uniform(-math.pi, math.pi, 40)
    for sign in (-1.0, 1.0):
        ach, valid = assemble.body_poses(rows, phi, sign)
        checked = 0
        for i, p in enumerate(rows):
            for j, f in enumerate(phi):
                ref = body_pose(p, f, sign)
                if ref is None or not valid[i, j]:
                    continue
                assert abs(ach[i, j, 0] - ref[0]) <= 1e-11 and abs(ach[i, j, 1] - ref[1]) <= 1e-11
                assert abs(angle_between(ach[i, j, 2], ref[2])) <= 1e-12
                assert -math.pi < ach[i, j, 2] <= math.pi
                checked += 1
        assert checked > 300


def test_residuals_are_the_pose_errors_with_the_wrapped_angle():
    rng = np.random.default_rng(4)
    rows = random_rows(rng, 5)
    poses = np.column_stack([rng.normal(size=7), rng.normal(size=7), rng.uniform(-math.pi, math.pi, 7)])
    phi = rng.uniform(-3 * math.pi, 3 * math.pi, (5, 7))  # input angles beyond a turn: the same linkage
    weight = 0.7
    r = LS.residuals(np.concatenate([rows, phi], 1), poses, -1.0, weight, None)
    for i in range(5):
        for k in range(7):
            ref = body_pose(rows[i], phi[i, k], -1.0)
            if ref is None:
                continue
            assert abs(r[i, 2 * k] - (ref[0] - poses[k, 0])) <= 1e-11
            assert abs(r[i, 2 * k + 1] - (ref[1] - poses[k, 1])) <= 1e-11
            assert abs(r[i, 14 + k] - weight * angle_between(ref[2], poses[k, 2])) <= 1e-12
            assert r[i, 21 + k] == 0.0  # it assembles: no violation


def brute_force(p, poses, grid, weight):
    """sum over the poses of the least cost over the grid angles (inf: none assembles)."""
    total = 0.0
    for pose in poses:
        costs = [math.inf]
        for f in grid:
            ref = body_pose(p, f, -1.0)
            if ref is not None:
                costs.append((ref[0] - pose[0]) ** 2 + (ref[1] - pose[1]) ** 2
                             + (weight * angle_between(ref[2], pose[2])) ** 2)
        total += min(costs)
    return total


def test_scores_take_each_poses_best_grid_angle_found_by_brute_force():
    """The coarse pass and its refinement against every grid angle tried: never below the
    brute force's minimum (a minimum over fewer angles) and equal to it (to round-off) for
    nearly every row."""
    rng = np.random.default_rng(5)
    rows = random_rows(rng, 60)
    true_phi = np.linspace(0.3, 5.8, 8)
    poses, _ = assemble.body_poses(PARAMS, true_phi, -1.0)
    poses[:, :2] += rng.normal(0.0, 0.02, (8, 2))
    grid = np.linspace(-np.pi, np.pi, 36, endpoint=False)  # coarse pass on every third: 12 angles
    weight = 0.9
    obj, best_phi = LS._scored(rows, poses, -1.0, grid, weight, None)
    equal = 0
    for i, p in enumerate(rows):
        total = brute_force(p, poses, grid, weight)
        if not math.isfinite(total):
            continue
        assert obj[i] >= total * (1 - 1e-12)
        equal += math.isclose(obj[i], total, rel_tol=1e-12)
    assert equal >= 0.8 * np.sum(np.isfinite(obj))
    # the generating linkage's own row: every pose at its best grid angle, near the true angle
    obj0, phi0 = LS._scored(PARAMS[None], poses, -1.0, grid, weight, None)
    step = 2 * np.pi / len(grid)
    assert np.all(np.abs([angle_between(a, b) for a, b in zip(phi0[0], true_phi)]) <= step)


def test_only_the_best_coarse_rows_are_refined(monkeypatch):
    """Beyond REFINE_ROWS rows, the best ones on the coarse angles (every third) are refined
    and the others keep their coarse score: the brute force over every third angle."""
    rng = np.random.default_rng(6)
    rows = random_rows(rng, 40)
    poses, _ = assemble.body_poses(PARAMS, np.linspace(0.3, 5.8, 6), -1.0)
    grid = np.linspace(-np.pi, np.pi, 36, endpoint=False)
    monkeypatch.setattr(LS, "REFINE_ROWS", 8)
    obj, _ = LS._scored(rows, poses, -1.0, grid, 0.9, None)
    coarse = np.array([brute_force(p, poses, grid[::3], 0.9) for p in rows])
    fine = np.array([brute_force(p, poses, grid, 0.9) for p in rows])
    refined = np.argsort(coarse, kind="stable")[:8]
    rest = np.setdiff1d(np.arange(40), refined)
    assert np.allclose(obj[rest], coarse[rest], rtol=1e-12, atol=0.0)
    assert np.all(obj[refined] <= coarse[refined] * (1 + 1e-12))
    assert np.all(obj[refined] >= fine[refined] * (1 - 1e-12))
    assert np.sum(np.isclose(obj[refined], fine[refined], rtol=1e-12)) >= 6
    assert np.sum(fine[refined] < coarse[refined] * (1 - 1e-9)) >= 4  # refining lowered them
