"""The house NNLS (linkcli.search.nnls, Lawson & Hanson ch. 23) against scipy.optimize.nnls
(the reference: the same algorithm's Fortran/C implementation) and the KKT conditions."""

from __future__ import annotations

import json

import numpy as np
import pytest

from linkcli.search.nnls import nnls


def _kkt(e, f, y, tol):
    w = e.T @ (f - e @ y)
    assert np.all(y >= 0.0)
    assert np.all(w <= tol)  # no index would lower the residual by growing
    assert np.all(np.abs(w[y > 0.0]) <= tol)  # stationary on the passive set


@pytest.mark.parametrize("shape", [(3, 2), (6, 6), (10, 4), (4, 10), (23, 40), (40, 23)])
def test_matches_scipy_and_meets_the_kkt_conditions(shape):
    from scipy.optimize import nnls as reference
    rng = np.random.default_rng(sum(shape))
    for _ in range(20):
        e = rng.normal(size=shape)
        f = rng.normal(size=shape[0])
        y, norm = nnls(e, f)
        y_ref, norm_ref = reference(e, f)
        assert norm == pytest.approx(norm_ref, rel=1e-9, abs=1e-12)
        if shape[0] >= shape[1]:  # full column rank: the minimizer is unique
            np.testing.assert_allclose(y, y_ref, rtol=1e-8, atol=1e-10)
        _kkt(e, f, y, 1e-9 * (1.0 + np.abs(e).sum()))


def test_known_solutions():
    # f inside the cone of E's columns: an exact fit; f in the negative orthant: y = 0
    e = np.array([[1.0, 0.0], [0.0, 2.0], [1.0, 1.0]])
    y, norm = nnls(e, e @ np.array([0.5, 0.25]))
    np.testing.assert_allclose(y, [0.5, 0.25], atol=1e-14)
    assert norm <= 1e-14
    y, norm = nnls(np.eye(3), np.array([-1.0, -2.0, 3.0]))
    np.testing.assert_allclose(y, [0.0, 0.0, 3.0], atol=0)
    assert norm == pytest.approx(np.sqrt(5.0), rel=1e-15)


def test_the_least_distance_problem_of_the_walk_is_solved_without_scipy():
    """search.polish.least_distance with the house NNLS: min |w| subject to g w >= h
    (Lawson & Hanson ch. 23), the same w as with scipy's, and scipy not loaded."""
    import subprocess
    import sys
    code = (
        "import json, sys, numpy as np\n"
        "from linkcli.search import polish\n"
        "from linkcli.search.nnls import nnls\n"
        "g = np.array([[1.0, 1.0], [1.0, -1.0], [-1.0, 0.0]]); h = np.array([1.0, -3.0, -5.0])\n"
        "w = polish.least_distance(g, h, nnls)\n"
        "assert 'scipy' not in sys.modules\n"
        "print(json.dumps(w.tolist()))\n")
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True).stdout
    w = np.array(json.loads(out))
    from linkcli.search import polish
    np.testing.assert_allclose(w, polish.least_distance(np.array([[1.0, 1.0], [1.0, -1.0], [-1.0, 0.0]]),
                                                        np.array([1.0, -3.0, -5.0])), rtol=1e-12)
    np.testing.assert_allclose(w, [0.5, 0.5], rtol=1e-12)  # the nearest point of the half-plane w1 + w2 >= 1
