"""Motion generation: poses, dyads, Burmester theory, assembly, least squares.

Every pose error is recomputed with an independent four-bar (circle intersection in
complex numbers, written here), and the Burmester count against a dense multi-start
Newton solve of the five circle equations |T_i M - G| = r, also written here."""

import numpy as np
import pytest

from linkcli.types.motion_generation import assemble, burmester, dyads, least_squares
from linkcli.types.motion_generation import poses as P

# ---------------------------------------------------------------- independent reference

def reference_body_pose(params, phi, sign):
    """Body pose of the four-bar at input phi: A on the input circle, B where the circles
    about A (radius b) and B0 (radius c) meet, on the side given by sign (open: the cross
    product (A - B0) x (B - B0) is negative)."""
    gx, gy, gang, d, a, b, c, px, py, cang = params
    a0 = complex(gx, gy)
    b0 = a0 + d * np.exp(1j * gang)
    A = a0 + a * np.exp(1j * (gang + phi))
    rho = abs(A - b0)
    along = (rho ** 2 + c ** 2 - b ** 2) / (2 * rho)  # from B0 towards A
    h = np.sqrt(c ** 2 - along ** 2)
    u = (A - b0) / rho
    B = b0 + along * u + sign * h * 1j * u  # +i u: cross(A - B0, B - B0) > 0 (crossed)
    e = (B - A) / abs(B - A)
    origin = A + e * complex(px, py)
    return np.array([origin.real, origin.imag, np.angle(e) + cang])


def reference_poses(params, phis, sign):
    return np.array([reference_body_pose(params, f, sign) for f in phis])


def angle_gap(x, y):
    return np.abs(np.angle(np.exp(1j * (np.asarray(x) - np.asarray(y)))))


def random_linkage(rng):
    """A crank-rocker (open branch) with a random placement and coupler frame."""
    while True:
        a, b, c, d = rng.uniform(1.0, 2.0), rng.uniform(3.0, 5.0), rng.uniform(2.5, 4.5), rng.uniform(3.0, 5.0)
        lengths = sorted([a, b, c, d])
        if a == lengths[0] and lengths[0] + lengths[3] < lengths[1] + lengths[2]:
            break
    return np.array([rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-np.pi, np.pi), d, a, b, c,
                     rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-np.pi, np.pi)])


def true_dyads(params):
    """(G, M) of the input and output dyads of a linkage, from the reference at phi = 0."""
    gx, gy, gang, d, a, b, c, px, py, cang = params
    pose0 = reference_body_pose(params, 0.0, -1.0)
    a0 = np.array([gx, gy])
    b0 = a0 + d * np.array([np.cos(gang), np.sin(gang)])
    A = a0 + a * np.array([np.cos(gang), np.sin(gang)])
    body_a = P.to_body(pose0, A)
    # B: coupler frame point (b, 0), i.e. A + b e; e from the body angle
    theta = pose0[2] - cang
    B = A + b * np.array([np.cos(theta), np.sin(theta)])
    return (a0, body_a), (b0, P.to_body(pose0, B))


def linkage_pose_errors(link, targets):
    sign = link["branch_signs"]
    got = np.array([reference_body_pose(link["params"], f, s)
                    for f, s in zip(link["input_angles"], sign)])
    return np.linalg.norm(got[:, :2] - targets[:, :2], axis=1), angle_gap(got[:, 2], targets[:, 2])


# ---------------------------------------------------------------- poses and dyads

def test_pole_is_fixed_by_the_displacement():
    rng = np.random.default_rng(5)
    ps = np.c_[rng.normal(size=(2, 2)), rng.normal(size=2)]
    pole = P.pole(ps[0], ps[1])
    body_point = P.to_body(ps[0], pole)  # the body point at the pole in pose 1 ...
    assert np.allclose(P.to_global(ps[1], body_point), pole, atol=1e-12)  # ... is there in pose 2


def test_bilinear_form_and_standard_form_agree_with_distances():
    rng = np.random.default_rng(6)
    ps = np.c_[rng.normal(size=(4, 2)), rng.normal(size=4)]
    g, m = rng.normal(size=(7, 2)), rng.normal(size=(7, 2))
    pts = np.array([[P.to_global(p, mm) for p in ps] for mm in m])
    d2 = np.sum((pts - g[:, None, :]) ** 2, -1)
    assert np.allclose(dyads.coefficients(ps).residuals(g, m), d2[:, 1:] - d2[:, :1], atol=1e-12)
    sol = dyads.three_pose_dyad(ps[:3], ground=g[0])
    assert np.max(np.abs(dyads.standard_form(ps[:3], g[0], sol.moving)[-1])) < 1e-12


def test_two_poses_lines_hold_the_dyads():
    rng = np.random.default_rng(7)
    ps = np.c_[rng.normal(size=(2, 2)), rng.normal(size=2)]
    g = rng.normal(size=2)
    line = dyads.moving_pivot_line(ps, g)
    for t in (-3.0, 0.0, 2.5):
        assert abs(dyads.circle_residuals(ps, g, line.point + t * line.direction)[0]) < 1e-12
    m = rng.normal(size=2)
    gl = dyads.ground_pivot_line(ps, m)
    assert abs(dyads.circle_residuals(ps, gl.point + 4 * gl.direction, m)[0]) < 1e-12
    assert dyads.moving_pivot_line(ps, P.pole(ps[0], ps[1])).status == "any"


@pytest.mark.parametrize("seed", range(6))
def test_three_poses_with_given_ground_pivots_are_reproduced_exactly(seed):
    rng = np.random.default_rng(seed)
    params = random_linkage(rng)
    phis = np.sort(rng.uniform(0, 2 * np.pi, 3))
    targets = reference_poses(params, phis, -1.0)
    (a0, _), (b0, _) = true_dyads(params)
    first = dyads.three_pose_dyad(targets, ground=a0)
    second = dyads.three_pose_dyad(targets, ground=b0)
    link = assemble.linkage_from_dyads(targets, (a0, first.moving), (b0, second.moving))
    pos, ang = linkage_pose_errors(link, targets)
    assert pos.max() <= 1e-9 and ang.max() <= 1e-9
    assert np.allclose(link["params"][3:7], params[3:7], atol=1e-9)


def test_three_poses_with_given_moving_pivots_give_the_ground_pivots():
    rng = np.random.default_rng(11)
    params = random_linkage(rng)
    targets = reference_poses(params, [0.3, 1.4, 2.2], -1.0)
    (a0, ma), (b0, mb) = true_dyads(params)
    assert np.allclose(dyads.three_pose_dyad(targets, moving=ma).ground, a0, atol=1e-9)
    assert np.allclose(dyads.three_pose_dyad(targets, moving=mb).ground, b0, atol=1e-9)


def test_three_poses_degenerate_cases_are_reported():
    # a pure translation along x: every body point moves on a straight line
    ps = np.array([[0.0, 0.0, 0.3], [1.0, 0.0, 0.3], [2.0, 0.0, 0.3]])
    assert dyads.three_pose_dyad(ps, moving=[0.5, 0.2]).status == "degenerate"
    # the ground pivot at the pole P12: row f_2 vanishes, M is not unique
    ps = np.array([[0.0, 0.0, 0.0], [1.0, 0.5, 0.7], [0.2, 1.5, 1.5]])
    assert dyads.three_pose_dyad(ps, ground=P.pole(ps[0], ps[1])).status == "degenerate"


# ---------------------------------------------------------------- four poses

def test_four_pose_curve_samples_satisfy_the_equal_distances():
    rng = np.random.default_rng(21)
    for _ in range(3):
        ps = np.c_[rng.normal(size=(4, 2)), rng.normal(size=4)]
        curve = burmester.centre_point_curve(ps, samples=361)
        g, m = curve.pairs()
        assert len(g) > 100
        pts = np.stack([P.to_global(p, m) for p in ps], 1)
        r = np.linalg.norm(pts - g[:, None, :], axis=-1)
        assert np.max(np.abs(r - r[:, :1])) <= 1e-9 * P.characteristic_length(ps)
        # the circle-point curve is the moving pivot at pose 1
        assert np.allclose(curve.circle.reshape(-1, 2)[np.all(np.isfinite(curve.circle.reshape(-1, 2)), 1)],
                           P.to_global(ps[0], m), atol=1e-12)
        # the six poles lie on the centre-point curve: each admits a moving pivot (rank <= 2)
        rows = dyads.coefficients(ps).moving_rows(curve.poles)
        assert np.all(np.abs(np.linalg.det(rows)) <= 1e-9 * np.abs(rows).max() ** 3)


# ---------------------------------------------------------------- five poses

def multistart_count(ps, starts=3000, seed=0):
    """Independent count of real dyads: damped Newton on |T_i M - G| - r = 0 (i = 1..5, five
    unknowns G, M, r) from many starts, deduplicated."""
    rng = np.random.default_rng(seed)
    L = P.characteristic_length(ps)
    cen = ps[:, :2].mean(0)
    spread = L * np.exp(rng.uniform(np.log(0.3), np.log(30.0), (starts, 1)))
    g = cen + spread * rng.uniform(-1, 1, (starts, 2))
    m = spread * rng.uniform(-1, 1, (starts, 2))
    c, s = np.cos(ps[:, 2]), np.sin(ps[:, 2])
    def positions(m):
        return np.stack([c * m[:, None, 0] - s * m[:, None, 1] + ps[:, 0],
                         s * m[:, None, 0] + c * m[:, None, 1] + ps[:, 1]], -1)
    r = np.linalg.norm(positions(m)[:, 0] - g, axis=-1)
    z = np.column_stack([g, m, r])
    for _ in range(200):
        pts = positions(z[:, 2:4])
        diff = pts - z[:, None, 0:2]
        dist = np.linalg.norm(diff, axis=-1)
        f = dist - z[:, 4:5]
        u = diff / dist[..., None]
        jm = np.stack([u[..., 0] * c + u[..., 1] * s, -u[..., 0] * s + u[..., 1] * c], -1)
        jac = np.concatenate([-u, jm, -np.ones((starts, 5, 1))], -1)
        jtj = np.einsum("nki,nkj->nij", jac, jac)
        lam = 1e-9 * np.trace(jtj, axis1=1, axis2=2)[:, None, None] * np.eye(5)
        step = np.linalg.solve(jtj + lam, np.einsum("nki,nk->ni", jac, f)[..., None])[..., 0]
        z = z - np.clip(step, -L, L)
    pts = positions(z[:, 2:4])
    f = np.linalg.norm(pts - z[:, None, 0:2], axis=-1) - z[:, 4:5]
    good = np.max(np.abs(f), 1) < 1e-9 * L
    found = []
    for row in z[good]:
        if np.linalg.norm(row[:4]) < 1e4 * L and all(np.linalg.norm(row[:4] - q[:4]) > 1e-6 * L for q in found):
            found.append(row)
    return np.array(found)


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(4))
def test_five_poses_burmester_dyads_contain_the_linkage_and_match_an_independent_count(seed):
    rng = np.random.default_rng(100 + seed)
    params = random_linkage(rng)
    phis = np.sort(rng.uniform(0, 2 * np.pi, 5))
    targets = reference_poses(params, phis, -1.0)
    res = burmester.burmester_dyads(targets)
    for g, m in true_dyads(params):
        gap = np.min(np.linalg.norm(res.ground - g, axis=1) + np.linalg.norm(res.moving - m, axis=1))
        assert gap < 1e-8
    assert res.resultant_degree <= 9 and res.roots >= len(res.ground)
    independent = multistart_count(targets)
    assert len(independent) == len(res.ground)
    # each candidate linkage of the generating pair reproduces the poses exactly
    cands = assemble.candidate_linkages(targets, res.ground, res.moving)
    assert len(cands) == len(res.ground) * (len(res.ground) - 1)
    for cand in cands:
        pos, ang = linkage_pose_errors(cand["linkage"], targets)
        assert pos.max() <= 1e-8 and ang.max() <= 1e-8


@pytest.mark.slow
def test_five_random_poses_count_matches_independent_count():
    rng = np.random.default_rng(77)
    counts = []
    for _ in range(3):
        ps = np.c_[rng.normal(size=(5, 2)), rng.uniform(-1.5, 1.5, 5)]
        res = burmester.burmester_dyads(ps)
        assert len(multistart_count(ps, seed=1)) == len(res.ground)
        counts.append(len(res.ground))
    assert all(c in (0, 2, 4) for c in counts)


# ---------------------------------------------------------------- defects

def test_branch_defect_is_flagged():
    rng = np.random.default_rng(3)
    params = random_linkage(rng)
    # poses 1 and 2 on the open branch, pose 3 on the crossed one
    targets = np.array([reference_body_pose(params, f, s) for f, s in ((0.2, -1), (1.0, -1), (2.0, 1))])
    (a0, _), (b0, _) = true_dyads(params)
    link = assemble.linkage_from_dyads(targets, (a0, dyads.three_pose_dyad(targets, ground=a0).moving),
                                       (b0, dyads.three_pose_dyad(targets, ground=b0).moving))
    pos, ang = linkage_pose_errors(link, targets)
    assert pos.max() < 1e-9  # exact, yet on two branches
    checks = assemble.check_linkage(link["input"], link["coupler"], link["output"], link["ground"],
                                    link["input_angles"], link["branch_signs"])
    assert checks["branch_defect"] and "branch" in checks["defects"]


def test_order_defect_is_flagged_and_ordered_poses_are_not():
    """A crank reaches any three poses in cyclic order in one sense or the other; four
    poses out of cyclic order are an order defect."""
    rng = np.random.default_rng(4)
    params = random_linkage(rng)
    pair = true_dyads(params)
    cases = (([0.2, 2.0, 1.0, 3.0], True), ([0.2, 1.0, 2.0, 3.0], False),
             ([3.0, 2.0, 1.0, 0.2], False), ([2.0, 3.0, 0.2, 1.0], False), ([0.2, 2.0, 1.0], False))
    for phis, expect in cases:
        targets = reference_poses(params, phis, -1.0)
        link = assemble.linkage_from_dyads(targets, *pair)
        assert np.max(angle_gap(link["input_angles"], phis)) < 1e-9
        checks = assemble.check_linkage(link["input"], link["coupler"], link["output"], link["ground"],
                                        link["input_angles"], link["branch_signs"])
        assert checks["order_defect"] is expect and not checks["branch_defect"]
        assert checks["input_is_crank"]


# ---------------------------------------------------------------- many poses

@pytest.mark.slow
def test_many_noisy_poses_reach_at_most_the_generating_objective():
    rng = np.random.default_rng(8)
    params = random_linkage(rng)
    phis = np.linspace(0.0, 4.5, 9)
    clean = reference_poses(params, phis, -1.0)
    noisy = clean + np.c_[rng.normal(scale=0.03, size=(9, 2)), rng.normal(scale=0.02, size=9)]
    w = P.characteristic_length(noisy)
    gen = np.sum(np.sum((clean[:, :2] - noisy[:, :2]) ** 2, 1) + (w * angle_gap(clean[:, 2], noisy[:, 2])) ** 2)
    res = least_squares.solve_least_squares(noisy, seed=0)
    assert res["feasible"]
    got = reference_poses(res["params"], res["input_angles"], -1.0 if res["branch"] == "open" else 1.0)
    mine = np.sum(np.sum((got[:, :2] - noisy[:, :2]) ** 2, 1) + (w * angle_gap(got[:, 2], noisy[:, 2])) ** 2)
    assert abs(mine - res["objective"]) <= 1e-9 * max(gen, 1e-12)
    assert mine <= gen * (1 + 1e-9)


def test_prescribed_timing_fits_exact_data_exactly():
    rng = np.random.default_rng(9)
    params = random_linkage(rng)
    phis = np.linspace(0.3, 3.0, 7)
    targets = reference_poses(params, phis, -1.0)
    lo, hi = least_squares.default_bounds(targets)
    res = least_squares.solve_least_squares(targets, (lo, hi), branch="open", timing="prescribed",
                                            input_angles=phis, seed=1)
    got = reference_poses(res["params"], res["input_angles"], -1.0)
    assert np.max(np.linalg.norm(got[:, :2] - targets[:, :2], axis=1)) < 1e-6


@pytest.mark.slow
def test_burmester_dyads_of_many_sets_side_by_side_are_each_sets_own():
    """Sets with 0, 2 and 4 real dyads solved side by side: each set's dyads are those the
    set alone gives (nothing of one set leaks into another), every one solves its own
    five-pose equations, and the count matches the independent multistart's."""
    rng = np.random.default_rng(78)
    sets = [np.c_[rng.normal(size=(5, 2)), rng.uniform(-1.5, 1.5, 5)] for _ in range(6)]
    params = random_linkage(rng)
    sets.append(reference_poses(params, np.sort(rng.uniform(0, 2 * np.pi, 5)), -1.0))
    many = burmester.burmester_dyads_many(np.array(sets))
    assert len(many) == len(sets) and burmester.burmester_dyads_many(np.zeros((0, 5, 3))) == []
    for poses, res in zip(sets, many):
        alone = burmester.burmester_dyads(poses)
        assert np.array_equal(res.ground, alone.ground) and np.array_equal(res.moving, alone.moving)
        assert len(multistart_count(poses, seed=1)) == len(res.ground)
        if len(res.ground):
            assert np.max(np.abs(dyads.circle_residuals(poses, res.ground[:, None], res.moving[:, None]))) < 1e-8
    assert {len(r.ground) for r in many} >= {2, 4}


def test_roots_of_many_polynomials_are_numpys_roots():
    rng = np.random.default_rng(9)
    polys = rng.normal(size=(12, 6))
    polys[3, 0] = 0.0  # a leading zero: a lower degree
    polys[5, -1] = 0.0  # a trailing zero: a root at 0
    polys[7] = 0.0  # no polynomial
    for mine, numpys in zip(burmester.roots_many(polys), (np.roots(p) for p in polys)):
        assert np.array_equal(mine, numpys)
