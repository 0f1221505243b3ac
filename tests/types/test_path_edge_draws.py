"""Free timing's rounds at the crank-rocker's edge (path_generation.starts.edge_shapes,
solve.EDGE_EVERY): the shapes are crank-rockers at the edge, inside the bounds, checked here
with the Grashof sums written out; they serve only the designs they are made for; and
closed18_free, whose best lies on that edge, is found there twice."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest
from conftest import ROOT
from test_path_settle import EDGE_SLSQP

CLOSED18 = ROOT / "problems" / "bench" / "closed18_free.toml"


def design_from(text: str):
    from linkcli.reading.load import load
    from linkcli.types.path_generation.model import build

    return build(load("edge.toml", text.encode()))


def closed18_text(**replace) -> str:
    text = CLOSED18.read_text()
    for old, new in replace.items():
        assert old in text
        text = text.replace(old, new)
    return text


def test_edge_shapes_are_crank_rockers_at_the_edge_inside_the_bounds():
    from linkcli.types.path_generation import starts

    design = design_from(closed18_text())
    rng = np.random.default_rng(5)
    x, _, _ = starts.draw(design, rng, 400)
    out = starts.edge_shapes(design, rng, x)
    assert np.array_equal(out[:, 6:], x[:, 6:])  # pivot, ground angle, timing: as drawn
    d, a, b, c = out[:, :4].T
    lengths = np.sort(out[:, :4], axis=1)
    s_l, p_q = lengths[:, 0] + lengths[:, 3], lengths[:, 1] + lengths[:, 2]
    assert np.all(a == lengths[:, 0])  # the input the shortest: a crank
    margin = (p_q - s_l) / p_q
    assert np.all(margin > 0.0) and np.all(margin <= 3e-2 * (1 + 1e-5))
    assert np.any(margin < 1e-4) and np.any(margin > 1e-2)  # log-uniform: near the change point and far
    ratio = a / d
    assert np.all(ratio >= 0.005 * (1 - 1e-6)) and np.all(ratio <= 0.12 * (1 + 1e-6))
    reach = np.hypot(out[:, 4], out[:, 5]) / a  # the coupler point from the crank pin, in inputs
    assert np.all(reach >= 0.3 * (1 - 1e-5)) and np.all(reach <= 30.0 * (1 + 1e-5))
    assert np.all(out[:, :6] >= design.lo[:6]) and np.all(out[:, :6] <= design.hi[:6])


def test_a_shape_no_scale_brings_inside_the_bounds_keeps_its_uniform_draw():
    """With the coupler point's x held within [1, 3], a shape whose point lies on the crank
    pin's other side (x < 0) has no factor that brings it inside: the row stays as drawn."""
    from linkcli.types.path_generation import starts

    design = design_from(closed18_text(**{"coupler_point = { x = [-50, 50]": "coupler_point = { x = [1, 3]"}))
    rng = np.random.default_rng(2)
    x, _, _ = starts.draw(design, rng, 300)
    out = starts.edge_shapes(design, rng, x)
    kept = np.all(out == x, axis=1)
    moved = ~kept
    assert kept.any() and moved.any()
    assert np.all(out[moved, 4] >= 1.0) and np.all(out[moved, 4] <= 3.0)
    assert np.all(out[:, :6] >= design.lo[:6]) and np.all(out[:, :6] <= design.hi[:6])


@pytest.mark.parametrize("change", [
    {'grashof = "crank-rocker"': 'grashof = "double-crank"'},
    {'branch = "open"': 'branch = "open"\ntransmission = [30, 150]'},
    {"input = [0, 50]": "input = 2.5"},
    {"coupler_point = { x = [-50, 50], y = [-50, 50] }": "coupler_point = { x = 1.5, y = [-50, 50] }"},
])
def test_edge_shapes_serve_only_a_free_crank_rocker_without_a_window(change):
    from linkcli.types.path_generation import starts

    assert starts.at_edge(design_from(closed18_text()))
    assert not starts.at_edge(design_from(closed18_text(**change)))


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1])
def test_closed18_free_is_found_twice_at_its_edge_optimum(seed):
    """Every round before the one a best may first be claimed at draws uniform lengths (and the
    atlas's starts); from there every second round draws at the edge. closed18_free ended
    `not-converged` on every seed (the atlas's first round alone reached its edge optimum):
    now `ok` there, within 2e-5 of the independent SLSQP value on the search's margin
    (test_path_settle.EDGE_SLSQP) and not above it, the output at its bound 50."""
    run = subprocess.run([sys.executable, "-m", "linkcli", "synth", str(CLOSED18), "--seed", str(seed), "-f", "json"],
                         capture_output=True, text=True, timeout=3600)
    assert run.returncode == 0, run.stderr
    out = json.loads(run.stdout)
    assert out["status"] == "ok"
    assert EDGE_SLSQP * (1 - 2e-5) <= out["error"]["objective"] <= EDGE_SLSQP
    assert math.isclose(out["linkage"]["output"], 50.0, rel_tol=1e-9)
    assert out["grashof"]["class"] == "crank-rocker"


# closed18_free's recorded best known (its file's comments): ground, input, coupler, output
EDGE_BEST = [17.95105359, 0.4206982487, 32.4696497, 49.9999999]


@pytest.mark.parametrize("lengths, like", [
    (EDGE_BEST, True),  # s + l short of p + q by 1e-7 of it, the input 0.023 of the ground
    ([6.0035, 6.0035, 6.23125, 6.23125], False),  # on the edge, but the input as long as the ground
    ([17.95105359, 0.4206982487, 32.4696497, 49.9], False),  # a small crank 2e-3 inside the edge
    ([17.95105359, 32.4696497, 0.4206982487, 49.9999999], False),  # the coupler the shortest: no crank
])
def test_edge_like_says_which_bests_are_small_cranks_at_the_edge(lengths, like):
    from linkcli.types.path_generation import starts

    assert starts.edge_like(np.array(lengths + [1.5, -0.9])) is like


@pytest.mark.parametrize("lengths", [EDGE_BEST, [10.0, 5.0, 12.0, 11.0]])
def test_the_edge_rounds_are_every_second_from_the_claim_round_behind_a_best_at_the_edge(monkeypatch, lengths):
    """Which rounds draw at the edge, recorded from multistart's calls in a search that never
    confirms (every round's best is new): every second round from the claim round on while
    the best is a small crank at the edge, none while it is not."""
    from linkcli.search.budget import Budget
    from linkcli.types.path_generation import solve
    from linkcli.types.path_generation.result import Candidate

    design = design_from(closed18_text())
    seen = []
    x = np.array(design.lo, dtype=float)
    x[:4] = lengths

    def fake_round(design, budget, rng, sizes, best_so_far=None, later=False, extras=None, edge=False):
        seen.extend([edge] * len(sizes))
        budget.add(sum(sizes))
        return [[Candidate(x.copy(), -1.0, 1.0, True)] for _ in sizes]

    ranks = iter(np.geomspace(1.0, 1e-9, 400))  # every rank lower than the last: a new best each round
    monkeypatch.setattr(solve, "one_round", fake_round)
    monkeypatch.setattr(solve, "_rank", lambda design, c: (False, 0.0, float(next(ranks))))
    monkeypatch.setattr(solve, "_ranked", lambda design, cands: list(cands))
    monkeypatch.setattr(solve, "_found_twice", lambda design, found, exact: False)
    solve.multistart(design, Budget(4_000_000), np.random.default_rng(0))
    claim = solve.CLAIM_ROUNDS["free"]
    assert len(seen) > claim + 2
    like = lengths == EDGE_BEST
    assert seen == [like and i >= claim and (i - claim) % solve.EDGE_EVERY == 0 for i in range(len(seen))]
