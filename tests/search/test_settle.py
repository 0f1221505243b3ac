"""The BLAS-free linear algebra (search.linalg) and the final Newton-KKT polish
(search.kkt), each against an independent reference: numpy's LAPACK for the algebra,
closed-form constrained optima for the polish. That a solver's stage does not follow the
BLAS kernel cannot be tested here (OpenBLAS reads OPENBLAS_CORETYPE when it loads):
benchmarks/compare_kernels.py checks that; these tests check the properties it rests on."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from linkcli.search import kkt, linalg


def _well_conditioned(rng, batch, n):
    """Random systems with singular values in [1, 10] (condition number <= 10)."""
    q1, _ = np.linalg.qr(rng.normal(size=(batch, n, n)))
    q2, _ = np.linalg.qr(rng.normal(size=(batch, n, n)))
    s = rng.uniform(1.0, 10.0, size=(batch, n))
    return np.einsum("bij,bj,bkj->bik", q1, s, q2)


@pytest.mark.parametrize("n", [1, 2, 5, 12])
def test_solve_matches_lapack_on_well_conditioned_stacks(n):
    rng = np.random.default_rng(n)
    a = _well_conditioned(rng, 40, n)
    b = rng.normal(size=(40, n))
    assert_allclose(linalg.solve(a, b), np.linalg.solve(a, b[..., None])[..., 0], rtol=0, atol=1e-12)
    many = rng.normal(size=(40, n, 3))
    assert_allclose(linalg.solve(a, many), np.linalg.solve(a, many), rtol=0, atol=1e-12)


def test_solve_needs_pivoting_and_marks_singular_systems():
    # a zero in the first pivot position: elimination without row swaps would divide by 0
    a = np.array([[[0.0, 1.0], [1.0, 0.0]], [[1.0, 2.0], [2.0, 4.0]]])
    x = linalg.solve(a, np.array([[2.0, 3.0], [1.0, 1.0]]))
    assert_allclose(x[0], [3.0, 2.0])
    assert np.all(np.isnan(x[1]))  # rank one: no solution is claimed


def test_products_match_numpy():
    rng = np.random.default_rng(3)
    a, j, x = rng.normal(size=(4, 3)), rng.normal(size=(10, 8, 5)), rng.normal(size=3)
    assert_allclose(linalg.gram(j), np.swapaxes(j, 1, 2) @ j, atol=1e-12)
    assert_allclose(linalg.matvec(a, x), a @ x, atol=1e-14)
    assert linalg.dot(x, x) == pytest.approx(float(x @ x), abs=1e-14)


def test_slopes_match_the_analytic_jacobian():
    def values(u):  # (N, 2) -> (N, 2)
        return np.stack([np.sin(3 * u[:, 0]) * u[:, 1], np.exp(u[:, 0] - u[:, 1])], axis=1)

    u = np.array([0.3, 0.7])
    v, jac = kkt.slopes(values, u)
    exact = np.array([[3 * np.cos(0.9) * 0.7, np.sin(0.9)], [np.exp(-0.4), -np.exp(-0.4)]])
    assert_allclose(v, values(u[None])[0])
    assert_allclose(jac, exact, rtol=0, atol=1e-11)


def test_slopes_on_and_near_a_bound_are_taken_at_the_point_itself():
    # one-sided stencils for the variables within 2 h of a bound; moving the whole point
    # inside instead would take every column elsewhere (an O(h) error in all of them)
    def values(u):  # (N, 3) -> (N, 2), curved in every variable
        return np.stack([np.sin(3 * u[:, 0]) * u[:, 1] ** 2 + u[:, 2] ** 3,
                         np.exp(u[:, 0] - u[:, 1]) * np.cos(2 * u[:, 2])], axis=1)

    for u in ([0.0, 1.0, 0.5], [1e-5, 0.5, 1.0 - 2e-5], [0.3, 0.0, 0.0]):
        u = np.array(u)
        x, y, z = u
        exact = np.array([[3 * np.cos(3 * x) * y * y, 2 * np.sin(3 * x) * y, 3 * z * z],
                          [np.exp(x - y) * np.cos(2 * z), -np.exp(x - y) * np.cos(2 * z),
                           -2 * np.exp(x - y) * np.sin(2 * z)]])
        v, jac = kkt.slopes(values, u)
        assert_allclose(v, values(u[None])[0])
        assert_allclose(jac, exact, rtol=0, atol=1e-9)


# ---------------------------------------------------------------- the KKT polish

def _circle_problem(u):
    """min (x - 1)^2 + (y - 1)^2 subject to x^2 + y^2 <= 1/2 and x >= 0.1: the optimum is
    the point of the circle nearest (1, 1), (1/2, 1/2), with multiplier 1 (grad f =
    (-1, -1) = -lambda * grad(x^2 + y^2) = -lambda (1, 1)); x >= 0.1 does not bind."""
    x, y = u
    return kkt.Point(f=(x - 1) ** 2 + (y - 1) ** 2, g=np.array([2 * (x - 1), 2 * (y - 1)]),
                     c=np.array([0.5 - x * x - y * y, x - 0.1]),
                     a=np.array([[-2 * x, -2 * y], [1.0, 0.0]]))


def test_settle_lands_on_a_curved_active_constraint_to_round_off():
    # started 1e-4 inside the circle: the constraint binds within ACTIVE only after a
    # first, unconstrained round breaks it; Newton on the Lagrangian's Hessian (by
    # differences of the gradients) ends on the circle
    out = kkt.settle(_circle_problem, np.array([0.49, 0.5]))
    assert out.converged
    assert_allclose(out.u, [0.5, 0.5], rtol=0, atol=1e-12)
    assert out.worst <= 1e-12


def _nearest_to(target, constraint):
    """The Point of min |u - target|^2 subject to constraint(u) = (c, dc/du) >= 0, with h
    the Hessian of f alone (2 I)."""
    target = np.asarray(target, dtype=float)

    def point(u):
        c, a = constraint(u)
        d = u - target
        return kkt.Point(float(d @ d), 2.0 * d, np.array([c]), np.array([a], dtype=float), h=2.0 * np.eye(2))

    return point


def test_settle_on_a_linear_constraint_with_a_given_hessian():
    # min (x - 0.8)^2 + (y - 0.9)^2 subject to x + y <= 1: projection of (0.8, 0.9) on the
    # line, (0.45, 0.55)
    point = _nearest_to((0.8, 0.9), lambda u: (1.0 - u[0] - u[1], [-1.0, -1.0]))

    out = kkt.settle(point, np.array([0.45 - 3e-8, 0.55]))
    assert out.converged
    assert_allclose(out.u, [0.45, 0.55], rtol=0, atol=1e-13)


def test_settle_releases_a_bound_and_a_constraint_that_do_not_bind():
    # min (x + 1)^2 + (y - 0.3)^2 in the unit box subject to y <= 0.8: x sits on its lower
    # bound (the gradient pushes out), y is interior at 0.3; starting from y at its upper
    # bound 1 (held there first) and on y = 0.8 (within ACTIVE), both must be released
    point = _nearest_to((-1.0, 0.3), lambda u: (0.8 - u[1], [0.0, -1.0]))

    for start in ([1e-9, 1.0], [0.0, 0.8 - 1e-9]):
        out = kkt.settle(point, np.array(start))
        assert out.converged
        assert_allclose(out.u, [0.0, 0.3], rtol=0, atol=1e-13)


def test_settle_adds_a_constraint_that_a_failed_round_crossed():
    # min (x - 3)^2 + (y - 0.5)^2 in the unit box subject to x <= 0.6, started 1e-6 inside
    # (not within ACTIVE): the unconstrained round runs into the box at x = 1 and fails
    # there, having crossed x = 0.6; the constraint binds, the optimum is (0.6, 0.5)
    point = _nearest_to((3.0, 0.5), lambda u: (0.6 - u[0], [-1.0, 0.0]))

    out = kkt.settle(point, np.array([0.6 - 1e-6, 0.2]))
    assert out.converged
    assert_allclose(out.u, [0.6, 0.5], rtol=0, atol=1e-13)


def test_settle_adds_the_active_constraints_curvature_to_a_model_of_f_alone():
    # min (x - 3)^2 + (y - 1.8)^2 subject to x^2 + y^2 <= 1/2: the optimum is (3, 1.8)
    # scaled to radius sqrt(1/2), multiplier lambda = 3 / x* - 1 ~ 3.9 (2 (p - t) =
    # -2 lambda p). With h the Hessian of f alone (2 I) Newton misses the circle's
    # curvature (the Lagrangian's is 2 (1 + lambda) I): along the circle its error grows
    # by a factor lambda a step; `curvature` adds it by differences, and without it the
    # steps that grow are corrected along themselves (the secant update, `kkt._secant`)
    point = _nearest_to((3.0, 1.8), lambda u: (0.5 - u[0] ** 2 - u[1] ** 2, [-2 * u[0], -2 * u[1]]))

    best = np.array([1.0, 0.6]) * math.sqrt(0.5) / math.hypot(1.0, 0.6)
    start = np.array([0.2, 0.6])
    for curvature in (True, False):
        out = kkt.settle(point, start, curvature=curvature)
        assert out.converged
        assert_allclose(out.u, best, rtol=0, atol=1e-12)


def test_settle_is_deterministic_and_independent_of_the_start_within_its_basin():
    # a least-squares fit with a binding constraint, from three starts near the optimum:
    # the same point to round-off, and the same bits when run twice
    t = np.linspace(0.0, 1.0, 9)
    data = 0.3 + 0.5 * t + 0.2 * t * t

    def point(u):  # line fit a + b t, subject to a + b <= 0.75 (unconstrained: a + b = 1)
        r = u[0] + u[1] * t - data
        j = np.stack([np.ones_like(t), t], axis=1)
        return kkt.Point(float(r @ r), 2.0 * j.T @ r, np.array([0.75 - u[0] - u[1]]),
                         np.array([[-1.0, -1.0]]), h=2.0 * j.T @ j)

    # closed form: minimize |A x - d|^2 on a + b = 0.75, by substitution a = 0.75 - b
    col = t - 1.0
    b = float(col @ (data - 0.75) / (col @ col))
    expected = np.array([0.75 - b, b])
    ends = [kkt.settle(point, expected + np.array(dx)).u for dx in ([1e-6, -2e-6], [-3e-6, 1e-6], [0.0, 0.0])]
    for end in ends:
        assert_allclose(end, expected, rtol=0, atol=1e-12)
    again = kkt.settle(point, expected + np.array([1e-6, -2e-6])).u
    assert again.tobytes() == ends[0].tobytes()
    assert math.isclose(float(np.sum(expected)), 0.75)


def test_settle_with_two_active_constraints_that_coincide_on_the_free_variables():
    # min (x - 0.9)^2 + (y - 0.6)^2 + (z - 1.3)^2 in the unit box subject to
    # c1 = 0.5 - x - 0.2 z >= 0 and c2 = 0.7 - x - 0.4 z >= 0. z sits on its upper bound 1
    # (the gradient pushes out), where both rows read 0.3 - x: the KKT matrix holding both
    # is singular (arc6_timed's two Grashof inequalities once ground and output are at
    # their bounds); one of them carries the multiplier. Closed form: (0.3, 0.6, 1).
    def point(u):
        x, y, z = u
        return kkt.Point((x - 0.9) ** 2 + (y - 0.6) ** 2 + (z - 1.3) ** 2,
                         np.array([2 * (x - 0.9), 2 * (y - 0.6), 2 * (z - 1.3)]),
                         np.array([0.5 - x - 0.2 * z, 0.7 - x - 0.4 * z]),
                         np.array([[-1.0, 0.0, -0.2], [-1.0, 0.0, -0.4]]), h=2.0 * np.eye(3))

    out = kkt.settle(point, np.array([0.3, 0.5, 1.0]))
    assert out.converged
    assert_allclose(out.u, [0.3, 0.6, 1.0], atol=1e-12)
    assert out.worst <= 1e-12
    assert kkt.independent_rows(np.array([[-1.0, 0.0], [-1.0, 0.0], [0.0, 2.0]])) == [0, 2]


@pytest.mark.parametrize("n", [1, 3, 9, 12])
def test_solve_spd_matches_lapack_and_marks_indefinite_systems(n):
    rng = np.random.default_rng(10 + n)
    j = rng.normal(size=(30, 2 * n, n))
    a = np.einsum("bmi,bmj->bij", j, j) + 1e-3 * np.eye(n)  # damped normal equations
    b = rng.normal(size=(30, n))
    assert_allclose(linalg.solve_spd(a, b), np.linalg.solve(a, b[..., None])[..., 0], rtol=1e-9, atol=1e-9)
    indefinite = np.array([np.diag([1.0] * (n - 1) + [-1.0]), np.zeros((n, n))])
    assert np.all(np.isnan(linalg.solve_spd(indefinite, np.ones((2, n)))))


def _arrow_objective(u):
    """f = sum_i s_i^2, s_i = p0 cos t_i + p1 t_i^2 + t_i, u = (p0, p1, t_1..t_k): each t_i
    enters its own term alone (free timing's structure). Returns the kkt.Point with the
    closed-form gradient, and the closed-form Hessian."""
    p0, p1, t = u[0], u[1], u[2:]
    s = p0 * np.cos(t) + p1 * t ** 2 + t
    ds = -p0 * np.sin(t) + 2 * p1 * t + 1  # d s_i / d t_i
    g = np.concatenate([[np.sum(2 * s * np.cos(t)), np.sum(2 * s * t ** 2)], 2 * s * ds])
    k = len(t)
    h = np.zeros((k + 2, k + 2))
    h[0, 0], h[0, 1], h[1, 1] = np.sum(2 * np.cos(t) ** 2), np.sum(2 * np.cos(t) * t ** 2), np.sum(2 * t ** 4)
    h[0, 2:] = 2 * ds * np.cos(t) - 2 * s * np.sin(t)
    h[1, 2:] = 2 * ds * t ** 2 + 4 * s * t
    h[2:, 2:] = np.diag(2 * ds ** 2 + 2 * s * (-p0 * np.cos(t) + 2 * p1))
    h = np.triu(h) + np.triu(h, 1).T
    return kkt.Point(float(np.sum(s * s)), g, np.zeros(0), np.zeros((0, k + 2))), h


def test_a_grouped_hessian_matches_the_closed_form_with_two_gradients_a_group():
    """kkt's differenced Hessian with the separable variables taken together (column
    grouping): the closed-form Hessian of an arrow-structured objective, from 2 x 3
    gradients (p0, p1, the angles together) instead of 2 x 7."""
    u = np.array([0.6, 0.3, 0.1, 0.25, 0.4, 0.55, 0.8])
    calls = []

    def evaluate(v):
        calls.append(1)
        return _arrow_objective(v)[0]

    exact = _arrow_objective(u)[1]
    grouped = kkt._lagrangian_hessian(lambda us: [evaluate(v) for v in us], u, [], np.zeros(0), 1e-5,
                                      groups=[np.array([0]), np.array([1]), np.arange(2, 7)])
    assert len(calls) == 6
    assert_allclose(grouped, exact, rtol=0, atol=1e-8)
    calls.clear()
    alone = kkt._lagrangian_hessian(lambda us: [evaluate(v) for v in us], u, [], np.zeros(0), 1e-5)
    assert len(calls) == 14
    assert_allclose(alone, exact, rtol=0, atol=1e-8)


def test_the_differenced_hessian_evaluates_its_points_in_calls_of_bounded_size(monkeypatch):
    """`_lagrangian_hessian` hands `points` as many groups' point pairs a call as BATCH_ROWS
    allows (slopes' 4n + 1 rows a point): all of them at once when small, one pair a call at
    the least; the Hessian is the same either way."""
    u = np.array([0.6, 0.3, 0.1, 0.25, 0.4, 0.55, 0.8])
    groups = [np.array([0]), np.array([1]), np.arange(2, 7)]
    calls = []

    def points(us):
        calls.append(len(us))
        return [_arrow_objective(v)[0] for v in us]

    batched = kkt._lagrangian_hessian(points, u, [], np.zeros(0), 1e-5, groups=groups)
    assert calls == [6]
    calls.clear()
    monkeypatch.setattr(kkt, "BATCH_ROWS", 1)
    one_by_one = kkt._lagrangian_hessian(points, u, [], np.zeros(0), 1e-5, groups=groups)
    assert calls == [2, 2, 2]
    assert np.array_equal(batched, one_by_one)


def _large_residual(lam: float, counter: list):
    """Dennis & Schnabel (Numerical Methods for Unconstrained Optimization, 1983, example
    10.2.4): r(x) = (x + 1, lam x^2 + x - 1), minimum at x = 0 (g = 2 J^T r = 0 there for
    every lam) with Hessian 2 (2 - 2 lam), Gauss-Newton's 2 J^T J = 4: for lam < -1 its
    steps grow by |1 - (2 - 2 lam) / 2| a step. x = 4 (u - 1/2) on the unit box; h is
    Gauss-Newton's; a linear constraint x <= 0.5 (inactive) rides along."""

    def point(u):
        counter.append(1)
        x = 4.0 * (float(u[0]) - 0.5)
        r = np.array([x + 1.0, lam * x * x + x - 1.0])
        j = np.array([[1.0], [2.0 * lam * x + 1.0]]) * 4.0
        return kkt.Point(float(r @ r), 2.0 * j.T @ r, np.array([0.5 - x]), np.array([[-4.0]]), h=2.0 * j.T @ j)

    return point


def test_stalled_curvature_settles_where_gauss_newton_steps_grow():
    # lam = -2: Gauss-Newton's steps double each time from 1e-6 off the minimum; "stalled"
    # switches to the differenced Hessian once they stop shrinking, and Gauss-Newton alone
    # corrects its model along the steps taken (`kkt._secant`) from then on
    start = np.array([0.5 + 1e-6])
    for curvature in ("stalled", False):
        out = kkt.settle(_large_residual(-2.0, []), start, curvature=curvature)
        assert out.converged
        assert_allclose(out.u, [0.5], rtol=0, atol=1e-12)


@pytest.mark.parametrize("lam", [-0.95, -1.5, -3.0, 0.9])
def test_gauss_newton_settles_where_it_misses_a_residuals_curvature(lam):
    # Dennis & Schnabel's example 10.2.4 again: Gauss-Newton's error is multiplied by
    # 1 - (2 - 2 lam) / 2 = lam a step, so lam = -0.95 swings back and forth 30 steps
    # without settling, and lam < -1 grows. The secant correction gives the model the true
    # curvature 2 (2 - 2 lam) along the steps: the minimum x = 0 (u = 1/2) to round-off
    out = kkt.settle(_large_residual(lam, []), np.array([0.5 + 1e-3]))
    assert out.converged
    assert_allclose(out.u, [0.5], rtol=0, atol=1e-12)


def _valley_to_a_bound(u):
    """Least squares r = (10 (y - x/2 - 0.2), 0.1 (x - 2)) on the unit box: a steep valley
    along y = x/2 + 0.2 that falls towards x = 2, outside the box. Gauss-Newton is exact
    (r is linear): its first step lands on (2, 1.2). The optimum on the box: x at its
    upper bound 1 and y on the valley's floor, 0.7, f = 0.01 (closed form: with x = 1 the
    first residual vanishes at y = 0.7, and df/dx = -0.18 < 0 there pushes x outwards)."""
    x, y = u
    r = np.array([10.0 * (y - 0.5 * x - 0.2), 0.1 * (x - 2.0)])
    j = np.array([[-5.0, 10.0], [0.1, 0.0]])
    return kkt.Point(float(r @ r), 2.0 * j.T @ r, np.zeros(0), np.zeros((0, 2)), h=2.0 * j.T @ j)


@pytest.mark.parametrize("start", [[0.2, 0.3], [0.5, 0.1], [0.0, 0.9]])
def test_settle_stops_a_long_newton_step_at_the_bound_it_crosses(start):
    # clipped to the box, Newton's step leaves the valley and its line search crawls
    # towards x = 1 by halvings without arriving; stopped where x meets its bound (the
    # ratio test) and held there, the next round settles y on the valley's floor
    out = kkt.settle(_valley_to_a_bound, np.array(start))
    assert out.converged
    assert_allclose(out.u, [1.0, 0.7], rtol=0, atol=1e-12)
    assert out.f == pytest.approx(0.01, rel=1e-12)


def test_stalled_curvature_costs_nothing_where_gauss_newton_converges():
    # lam = 0.1: Gauss-Newton converges (linearly, fast: ratio 0.1); a linear constraint
    # binds: min (x - 0.9)^2 on x <= 0.5 with a multiplier. "stalled" evaluates as
    # curvature=False does; True differences the constraint's (zero) curvature each step
    def run(curvature):
        calls = []

        def point(u):
            calls.append(1)
            x = float(u[0])
            return kkt.Point((x - 0.9) ** 2, np.array([2.0 * (x - 0.9)]), np.array([0.5 - x]),
                             np.array([[-1.0]]), h=np.array([[2.0]]))

        out = kkt.settle(point, np.array([0.5 - 1e-9]), curvature=curvature)
        assert out.converged and abs(out.u[0] - 0.5) <= 1e-12
        return len(calls)

    assert run("stalled") == run(False) < run(True)


def _jittered_valley(calls):
    """f = 1 + (x0^2 + 1e-8 x1^2) / 2 on x = u - 1/2, with Gauss-Newton's h exact and a
    deterministic jitter of 1e-15 on the gradient (the slopes' round-off): Newton's steps
    along the flat direction are the jitter over 1e-8, about 1e-7, and never fall below
    STEP_TOL; the model gains 1e-22 along them, round-off of f = 1."""

    def point(u):
        calls.append(1)
        x = np.asarray(u, float) - 0.5
        h = np.diag([1.0, 1e-8])
        jitter = 1e-15 * np.array([0.0, math.sin(1e9 * float(u[1]) + 7.0 * len(calls))])
        return kkt.Point(1.0 + 0.5 * float(x @ h @ x), h @ x + jitter, np.zeros(0), np.zeros((0, 2)), h=h)

    return point


def test_settle_ends_where_its_model_gains_only_round_off():
    # the steps hover at the jitter's ~1e-7 (each a new draw); the rescue stops at the first
    # iterate whose step is within PRINTED and whose model gains below ROUND_OFF of f, and
    # that point is the minimum to the flat direction's jitter (1e-15 / 1e-8)
    calls = []
    start = np.array([0.5 + 1e-3, 0.5 + 2e-7])
    out = kkt.settle(_jittered_valley(calls), start)
    assert out.converged
    assert abs(out.u[0] - 0.5) <= 1e-12 and abs(out.u[1] - 0.5) <= 1e-6
    assert out.f == pytest.approx(1.0, rel=1e-14, abs=0.0)


def test_the_round_off_rescue_needs_a_small_model_gain():
    # the same valley with f's constant 1 taken away: f itself is now 1e-22 at the start's
    # flat offset, so the model's gain is not round-off of f, and the jitter's steps fail
    def point(u, base=_jittered_valley([])):
        p = base(u)
        return kkt.Point(p.f - 1.0, p.g, p.c, p.a, h=p.h)

    out = kkt.settle(point, np.array([0.5 + 1e-3, 0.5 + 2e-7]))
    assert not out.converged


def _flat_along_a_circle(calls):
    """min (u0 - 1)^2 on the disc |u - (0.5, 0.5)| <= 0.4: the optimum (0.9, 0.5) in closed
    form (multiplier 0.25); f is flat in u1, so Gauss-Newton's h = diag(2, 0) and only
    the circle's own curvature holds u1 there (an epsilon level of a Pareto front)."""

    def point(u):
        calls.append(1)
        d = np.asarray(u, float) - 0.5
        c = 0.16 - float(d @ d)
        return kkt.Point((float(u[0]) - 1.0) ** 2, np.array([2.0 * (float(u[0]) - 1.0), 0.0]), np.array([c]),
                         np.array([-2.0 * d]), h=np.diag([2.0, 0.0]))

    return point


def test_whole_curvature_with_reuse_settles_a_level_held_by_a_constraint_alone(monkeypatch):
    # from 1e-3 off the optimum along the circle: with the whole differenced Hessian of the
    # Lagrangian (least-squares multipliers at the start) Newton lands on (0.9, 0.5) to
    # round-off; `reuse` forms that Hessian again only where a step left NEAR (the first,
    # 1e-3 long), not at every step nor for the settle's restart from its end
    formed = []
    original = kkt._lagrangian_hessian
    monkeypatch.setattr(kkt, "_lagrangian_hessian", lambda *a, **k: formed.append(1) or original(*a, **k))
    angle = 1e-3 / 0.4
    start = np.array([0.5 + 0.4 * math.cos(angle), 0.5 + 0.4 * math.sin(angle)])
    calls = []
    out = kkt.settle(_flat_along_a_circle(calls), start, multipliers=True, curvature="whole", reuse=True)
    assert out.converged
    assert_allclose(out.u, [0.9, 0.5], rtol=0, atol=1e-12)
    assert len(formed) == 2
    fresh = []
    again = kkt.settle(_flat_along_a_circle(fresh), start, multipliers=True, curvature="whole")
    assert again.converged and len(fresh) > len(calls)  # a Hessian every step without reuse
    assert_allclose(again.u, out.u, rtol=0, atol=1e-12)


def test_curvature_must_be_one_of_its_modes():
    with pytest.raises(ValueError):
        kkt.settle(_flat_along_a_circle([]), np.array([0.9, 0.5]), curvature="always")
