"""The lookup's vectorized parts against references written here, row by row: the best-k
selection (`_best`), the match of the allowed rows alone (`_similar`) and the scale
interval of many shapes (`starts.scale_interval`)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from linkcli.types.path_generation import atlas_starts as lookup
from linkcli.types.path_generation import starts as path_starts


@pytest.mark.parametrize("size, count", [(6400, 10), (6401, 10), (6400, 150), (130, 100), (100, 500), (64 * 40, 41)])
def test_best_takes_the_largest_positive_scores_ties_to_the_lower_row(size, count):
    rng = np.random.default_rng(size + count)
    score = rng.integers(0, 30, size).astype(np.float32) / 7  # many ties, and zeros
    score[rng.random(size) < 0.5] = 0.0
    positive = [i for i in range(size) if score[i] > 0.0]
    expected = sorted(positive, key=lambda i: (-float(score[i]), i))[:count]
    assert lookup._best(score, count).tolist() == expected


def test_best_of_no_positive_score_is_empty():
    assert len(lookup._best(np.zeros(200, dtype=np.float32), 5)) == 0


@pytest.mark.parametrize("share", [0.0, 0.1, 0.7, 1.0])
def test_similar_scores_the_allowed_rows_alone_and_the_others_zero(share):
    # the descriptors of 3 blocks of 64 rows (the last partly used), 2 queries; each row's
    # best |<X, Y>|^2 / (|X|^2 |Y|^2) written here in float64 (the products of these small
    # integers and the few roundings of float32 agree to 1e-6)
    rng = np.random.default_rng(7)
    blocks, width, rows = 3, 64, 170
    table = rng.integers(-200, 200, (blocks, 10, width)).astype(np.float32)
    scale = (1.0 / np.maximum(np.sum(table.astype(np.float64) ** 2, axis=1), 1.0)).astype(np.float32)
    allowed = (rng.random(rows) < share).astype(np.float32)
    queries = []
    for _ in range(2):
        q = rng.integers(-100, 100, 10).astype(float)
        cols = np.stack([np.concatenate([q[:5], q[5:]]), np.concatenate([-q[5:], q[:5]])], axis=1)
        queries.append((cols, 1.0 / float(q @ q)))
    best, _ = lookup._similar(table, scale, rows, queries, allowed)
    flat = table.transpose(0, 2, 1).reshape(-1, 10).astype(np.float64)[:rows]
    expected = np.zeros(rows)
    for i in range(rows):
        if allowed[i]:
            expected[i] = max(float(np.sum((cols.T @ flat[i]) ** 2)) * size * float(scale.reshape(-1)[i])
                              for cols, size in queries)
    assert np.all(best[allowed == 0] == 0.0)
    np.testing.assert_allclose(best, expected, rtol=1e-6, atol=0)


def test_scale_interval_keeps_every_scaled_length_and_coordinate_inside_its_bounds():
    rng = np.random.default_rng(3)
    lo = np.array([1.0, 0.5, 2.0, 1.0, -5.0, 0.0, 0, 0, 0])
    hi = np.array([50.0, 10.0, 40.0, 30.0, 8.0, 6.0, 0, 0, 0])
    design = SimpleNamespace(lo=lo, hi=hi)
    x = np.zeros((300, 9))
    x[:, :4] = rng.uniform(0.1, 3.0, (300, 4))
    x[:, 4:6] = rng.uniform(-2.0, 2.0, (300, 2))
    x[::7, 4] = 0.0  # a coordinate of 0 bounds no scale
    low, high = path_starts.scale_interval(design, x)
    for i in range(len(x)):
        s_lo, s_hi = 1e-12, np.inf
        for j in range(6):
            v = x[i, j]
            if v > 0:
                s_lo, s_hi = max(s_lo, lo[j] / v), min(s_hi, hi[j] / v)
            elif v < 0:
                s_lo, s_hi = max(s_lo, hi[j] / v), min(s_hi, lo[j] / v)
        assert low[i] == s_lo and high[i] == s_hi
