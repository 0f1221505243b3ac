"""The `size` objective measured for many designs at once (Measure.size_pieces_many, through
the four-bar home's joint_paths) against a per-design reference written here: the four-bar's
joints over a full turn in closed form (circle intersection), on a dense grid, and the
diagonal of the box they sweep; and the batch against the same designs one at a time."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import linkcli.pareto.run as run
from linkcli.pareto.objectives import Measure
from tests.conftest import run_cli

ROOT = Path(__file__).resolve().parents[2]


class _Captured(Exception):
    """Stops the run at its front."""


@pytest.fixture(scope="module")
def path10_space():
    """The problem and design space of benchmarks/pareto/path10.toml (its front not run)."""
    held = {}

    def grab(problem, space, found):
        held.update(problem=problem, space=space)
        raise _Captured

    real, run.solve_front = run.solve_front, grab
    try:
        run_cli("synth", str(ROOT / "benchmarks/pareto/path10.toml"), "--format", "json")
    finally:
        run.solve_front = real
    assert "space" in held  # the front is stopped where it starts (the CLI reports the stop)
    return held["problem"], held["space"]


def box_diagonal(fb, dense=400_001):
    """The box swept by A0, B0, A, B and P over a full turn of the input: B from the circles
    |B - A| = b, |B - B0| = c (open: left of A -> B0), P = A + px u + py u_perp, u along A -> B;
    the ground frame turned by ground_angle about A0 = ground_pivot. inf: no assembly."""
    a, b, c, d = fb.abcd
    phi = np.linspace(0.0, 2.0 * math.pi, dense)
    ax, ay = a * np.cos(phi), a * np.sin(phi)
    ex, ey = d - ax, -ay
    r = np.hypot(ex, ey)
    ex, ey = ex / r, ey / r
    along = (b * b - c * c + r * r) / (2.0 * r)
    h2 = b * b - along * along
    if np.any(h2 < 0):
        return math.inf
    side = 1.0 if fb.branch == "open" else -1.0
    h = side * np.sqrt(h2)
    bx, by = ax + along * ex - h * ey, ay + along * ey + h * ex
    pts = [(np.zeros_like(phi), np.zeros_like(phi)), (np.full_like(phi, d), np.zeros_like(phi)), (ax, ay), (bx, by)]
    if fb.coupler_point is not None:
        px, py = fb.coupler_point
        ux, uy = (bx - ax) / b, (by - ay) / b
        pts.append((ax + px * ux - py * uy, ay + px * uy + py * ux))
    cg, sg = math.cos(fb.ground_angle), math.sin(fb.ground_angle)
    xs = np.concatenate([fb.ground_pivot[0] + cg * x - sg * y for x, y in pts])
    ys = np.concatenate([fb.ground_pivot[1] + sg * x + cg * y for x, y in pts])
    return math.hypot(xs.max() - xs.min(), ys.max() - ys.min())


def designs(space, count, spread, seed):
    rng = np.random.default_rng(seed)
    free = space.hi > space.lo
    width = (space.hi - space.lo)[free]
    out = []
    for _ in range(count):
        x = np.array(space.x0, dtype=float)
        x[free] = np.clip(x[free] + spread * width * rng.standard_normal(int(free.sum())),
                          space.lo[free], space.hi[free])
        out.append(x)
    return out


def test_batched_size_is_the_box_diagonal_of_each_design(path10_space):
    problem, space = path10_space
    assert space.full_turn  # the file asks for a crank-rocker: the size is over the full turn
    measure = Measure(problem, space, ("error", "size"))
    xs = designs(space, 12, 0.03, 5) + designs(space, 6, 0.5, 6)
    sols = [space.solution(x) for x in xs]
    batch = measure.size_pieces_many(sols)
    finite = 0
    for sol, pieces in zip(sols, batch):
        ref = box_diagonal(sol.linkage)
        got = float(np.max(pieces)) if np.all(np.isfinite(pieces)) else math.inf
        if math.isinf(ref):
            assert math.isinf(got)
            continue
        finite += 1
        assert got == pytest.approx(ref, rel=1e-7)
    assert finite >= 10


def test_the_batch_gives_each_design_its_own_numbers(path10_space):
    problem, space = path10_space
    measure = Measure(problem, space, ("error", "size"))
    xs = designs(space, 40, 0.2, 7)
    sols = [space.solution(x) for x in xs]
    batch = measure.size_pieces_many(sols)
    for sol, pieces in zip(sols, batch):
        one = measure.size_pieces_many([sol])[0]
        assert np.array_equal(np.isfinite(one), np.isfinite(pieces))
        assert np.array_equal(one[np.isfinite(one)], pieces[np.isfinite(pieces)])
    many = measure.pieces_many(np.array(xs))
    k = measure.names.index("size")
    for p, pieces in zip(many, batch):
        assert np.array_equal(p[k], pieces)


def _each_skeleton(linkages, phi):
    from linkcli.mechanisms import of
    return [of(linkage).skeleton(row).joints for linkage, row in zip(linkages, phi)]


def test_joint_paths_are_each_linkages_skeleton():
    """The four-bar's batched closed forms (mixed branches, a crossed one, one that does not
    assemble everywhere, with and without coupler points: the latter through the protocol's
    default) and the protocol's default on another home (a slider-crank) give each linkage's
    own skeleton, bit for bit."""
    from linkcli.mechanisms import of
    from linkcli.mechanisms.four_bar.model import FourBar
    from linkcli.mechanisms.slider_crank.model import SliderCrank
    rng = np.random.default_rng(3)
    cases = [
        [FourBar(50, 20, 60, 45, "open", (10, 5), (3, -2), 0.4), FourBar(40, 15, 50, 40, "crossed", (-4, 8), (0, 0), 2.0),
         FourBar(30, 25, 10, 12, "open", (1, 1), (5, 5), -1.0)],  # the last does not assemble over a turn
        [FourBar(50, 20, 60, 45), FourBar(40, 15, 50, 40, "crossed", (-4, 8))],  # P on one only
        [SliderCrank(20, 60, 5), SliderCrank(15, 40, -3, "crossed", (5, 2))],
    ]
    for linkages in cases:
        phi = rng.uniform(-4.0, 4.0, size=(len(linkages), 37))
        home = type(of(linkages[0]))
        each = _each_skeleton(linkages, phi)
        if len({tuple(joints) for joints in each}) > 1:
            with pytest.raises(ValueError):
                home.joint_paths(linkages, phi)
            continue
        paths = home.joint_paths(linkages, phi)
        assert tuple(paths) == tuple(each[0])
        for k, joints in enumerate(each):
            for name, xy in joints.items():
                got = np.asarray(paths[name][k], dtype=float).reshape(-1, 2)
                want = np.asarray(xy, dtype=float).reshape(-1, 2)
                assert np.array_equal(np.isnan(got), np.isnan(want))
                assert np.array_equal(got[~np.isnan(got)], want[~np.isnan(want)])
