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


def reference_joints(fb, phi):
    """The paths of A0, B0, A, B and P (the home's order; P when the linkage has a coupler point)
    at input angles phi, or None where it does not assemble: B from the circles |B - A| = b,
    |B - B0| = c (open: left of A -> B0), P = A + px u + py u_perp, u along A -> B; the ground
    frame turned by ground_angle about A0 = ground_pivot."""
    a, b, c, d = fb.abcd
    ax, ay = a * np.cos(phi), a * np.sin(phi)
    ex, ey = d - ax, -ay
    r = np.hypot(ex, ey)
    ex, ey = ex / r, ey / r
    along = (b * b - c * c + r * r) / (2.0 * r)
    h2 = b * b - along * along
    if np.any(h2 < 0):
        return None
    h = (1.0 if fb.branch == "open" else -1.0) * np.sqrt(h2)
    bx, by = ax + along * ex - h * ey, ay + along * ey + h * ex
    pts = [(np.zeros_like(phi), np.zeros_like(phi)), (np.full_like(phi, d), np.zeros_like(phi)), (ax, ay), (bx, by)]
    if fb.coupler_point is not None:
        px, py = fb.coupler_point
        ux, uy = (bx - ax) / b, (by - ay) / b
        pts.append((ax + px * ux - py * uy, ay + px * uy + py * ux))
    cg, sg = math.cos(fb.ground_angle), math.sin(fb.ground_angle)
    return [(fb.ground_pivot[0] + cg * x - sg * y, fb.ground_pivot[1] + sg * x + cg * y) for x, y in pts]


def box_diagonal(fb, dense=400_001):
    """The diagonal of the box swept by every joint over a full turn of the input
    (`reference_joints` at `dense` angles, both ends included); inf: no assembly."""
    paths = reference_joints(fb, np.linspace(0.0, 2.0 * math.pi, dense))
    if paths is None:
        return math.inf
    xs = np.concatenate([x for x, _ in paths])
    ys = np.concatenate([y for _, y in paths])
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


def dense_joints(fb, dense=400_000):
    """Each joint's path over a full turn (`reference_joints` on a cyclic grid, no repeated end
    point), or None: no assembly."""
    return reference_joints(fb, np.arange(dense) * (2.0 * math.pi / dense))


def test_two_peaks_of_each_joint_against_a_dense_sweep(path10_space):
    """The lifted size's peaks (Measure.boxes_many, two a joint: the largest and the next local
    maximum within PEAK_WINDOW of the diagonal) against the local maxima of each joint's
    coordinate on a 400,000-angle cyclic sweep written here (rel 1e-7 of the diagonal), on
    designs where joints do peak twice (the rocker pin passing its circle's extreme on the way
    out and back, a coupler curve's two lobes)."""
    from linkcli.pareto.objectives import PEAK_WINDOW
    problem, space = path10_space
    measure = Measure(problem, space, ("error", "size"))
    xs = designs(space, 30, 0.2, 11)
    sols = [space.solution(x) for x in xs]
    boxes = measure.boxes_many(sols, peaks=2)
    twice = checked = 0
    for sol, box in zip(sols, boxes):
        paths = dense_joints(sol.linkage)
        if paths is None:
            assert not np.all(np.isfinite(box))
            continue
        xs_, ys_ = np.concatenate([p[0] for p in paths]), np.concatenate([p[1] for p in paths])
        diagonal = math.hypot(np.ptp(xs_), np.ptp(ys_))
        for side, (coord, sign) in enumerate([(0, 1.0), (0, -1.0), (1, 1.0), (1, -1.0)]):
            for joint, path in enumerate(paths):
                v = sign * path[coord]
                local = (v > np.roll(v, 1)) & (v >= np.roll(v, -1))
                peaks = np.sort(v[local])[::-1] if local.any() else np.array([v.max()])
                top = float(np.max(v))
                near = peaks[1:][peaks[1:] >= top - PEAK_WINDOW * diagonal]
                rival = peaks[1:][peaks[1:] >= top - 1.2 * PEAK_WINDOW * diagonal]
                if len(rival) != len(near) or np.any(near >= top - 0.8 * PEAK_WINDOW * diagonal) != bool(len(near)):
                    continue  # a rival at the window's edge: either answer is right
                want = sorted([top, float(near[0]) if len(near) else top])
                got = sorted((sign * box[side, joint]).tolist())
                assert got == pytest.approx(want, abs=1e-7 * diagonal)
                checked += 1
                twice += len(near) > 0
    assert checked >= 300 and twice >= 5


def test_the_lifted_level_holds_the_plain_level_designs(path10_space):
    """With the box's sides at a design's own box (Scalarized.lifted's unit), every side is
    beyond every peak (its rows >= 0, one of each side's 0) and the diagonal row is the plain
    level's largest size row: the same feasible designs, the same size."""
    from linkcli.pareto.scalarized import Scalarized
    from linkcli.search.budget import Budget
    problem, space = path10_space
    measure = Measure(problem, space, ("error", "size"))
    xs = [x for x in designs(space, 12, 0.05, 12) if np.isfinite(measure.values(x)[1])]
    eps = float(np.median([measure.values(x)[1] for x in xs]))
    scales = np.array([1.0, 50.0])
    plain = Scalarized(measure, 0, {1: eps}, scales, Budget(10**9))
    lifted = plain.lifted(xs[0])
    assert lifted is not plain and lifted.n_variables == plain.n_variables + 4
    holds = [0, 0]
    for x in xs:
        c_plain = plain.value(plain.unit(x))[1]
        c_lift = lifted.value(lifted.unit(x))[1]
        types = len(space.inequalities(x[None, :])[0])
        sides = c_lift[types:-1].reshape(4, -1)
        assert np.all(sides >= -1e-12) and np.all(np.min(sides, axis=1) <= 1e-12)
        assert c_lift[-1] == pytest.approx(float(np.min(c_plain[types:])), abs=1e-9)
        holds[bool(c_lift[-1] >= 0)] += 1
    assert min(holds) >= 2  # designs on both sides of the level


def test_a_level_whose_optimum_balances_two_peaks_settles(path10_space):
    """benchmarks/pareto/path10.toml's level 8 (size <= 118.1257...) from its polish's end (here
    as numbers): the coupler point's highest y peaks twice over the turn, 8e-5 apart there; the
    plain Newton settle fails on its first step (one bent piece), the lifted one converges to a
    KKT point with a lower error, where both peaks are the box's top (equal to 1e-9 of it)."""
    import linkcli.pareto.front as fr
    from linkcli.pareto.scalarized import Scalarized
    from linkcli.search.budget import Budget
    problem, space = path10_space
    measure = Measure(problem, space, ("error", "size"))
    x = np.array([55.04985844489492, 16.95175574385948, 32.975827936603196, 47.12122368448456, 39.76898037832842,
                  58.54265250207729, -11.946168527043369, -51.57652157915237, 0.9310495682811935, 3.8567485336256713])
    level = Scalarized(measure, 0, {1: 118.12570614167193}, np.array([72323.57785587196, 166.71718484978535]),
                       Budget(10**9))
    assert not fr._settle(level, level, x)[1]  # the plain settle alone
    end, settled = fr.settle(level, x)
    assert settled
    before, after = measure.values(x), measure.values(end)
    assert after[0] < before[0] and after[1] <= 118.12570614167193 * (1 + 1e-9)
    top_y = measure.boxes_many([space.solution(end)], peaks=2)[0][2]  # (joints, 2): each joint's two y peaks
    p = top_y[-1]  # the coupler point's
    assert p[0] != p[1] and abs(p[0] - p[1]) <= 1e-9 * after[1] and max(p) == pytest.approx(np.max(top_y), abs=1e-12)
