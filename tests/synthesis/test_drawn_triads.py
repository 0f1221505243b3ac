"""Designing drawn linkages whose plan has a class-III triad (issue 49: every six-bar searched).

The population's triads (drawn.population_groups: continuation over N designs at once, rows by
batched Newton) against the analysis's solver for one drawing at a time (drawn.solver with
drawn.groups: another formulation -- every group link's pose, twelve unknowns, LAPACK's solve --
and another continuation), and against rigidity itself (every link keeps its drawn distances);
a known Stephenson II's tracer path recovered from a perturbed drawing; the Stephenson II
topology searched and its result read back by analyze.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import ROOT, run_cli
from test_drawn_synthesis import perturbed_problem
from test_topology_sweep import PATH as SWEEP_PATH

# A Stephenson II six-bar driven at a binary crank (catalogue: "stephenson-ii, binary crank
# (triad), tracer P on coupler", its first starting drawing, rounded): the crank turns fully.
STEPHENSON_II = """
type = "path-generation"
title = "A Stephenson II six-bar's tracer"
[linkage]
mechanism = "drawn"
[joints]
O1 = { at = [53.7, -178.0], ground = true }
O2 = { at = [258.8, -185.7], ground = true }
A = { at = [54.5, -207.0] }
B = { at = [-44.7, -129.1] }
C = { at = [141.5, -160.0] }
D = { at = [-56.4, -199.1] }
E = { at = [142.1, -302.6] }
P = { at = [18.2, 0.0] }
[links]
crank = ["O1", "A"]
coupler = ["A", "B", "C", "P"]
rocker = ["O2", "D", "E"]
link = ["B", "D"]
link2 = ["C", "E"]
[drive]
crank = {}
"""


def _catalogue_drawing(label_part: str):
    from linkcli.mechanisms.drawn import catalogue
    choice = next(c for c in catalogue.choices("any six-bar", "path") if label_part in c.label)
    return catalogue.starting_drawings(choice, (0.0, 0.0, 100.0, 60.0), seed=0, count=1)[0]


def _rigid_distances(drawing, places, rows):
    """Every pair of joints on one link (or the ground) at `rows`: (drawn, found (R,)) pairs."""
    at = {j.name: np.array(j.at, dtype=float) for j in drawing.joints}
    groups = [[j.name for j in drawing.joints if j.ground]] + [list(k.joints) for k in drawing.links]
    for joints in groups:
        for i, a in enumerate(joints):
            for b in joints[i + 1:]:
                yield float(np.hypot(*(at[a] - at[b]))), np.hypot(*(places[a][rows] - places[b][rows]).T)


@pytest.mark.parametrize("label", ["stephenson-ii, ternary crank (triad), tracer P on link",
                                   "stephenson-ii, binary crank (triad), tracer P on coupler",
                                   "stephenson-iii, binary crank (triad), tracer P on link"])
def test_population_triads_match_the_analysis_solver(label):
    """60 random designs around a catalogued triad drawing x 40 random drive values over two
    turns either way: the population's validity is the analysis's, row for row (rows past a
    dead point, rows off the drawn branch), its places the analysis's within 1e-8 of the size;
    and every valid row keeps every link rigid (independently of both solvers)."""
    from linkcli.mechanisms.drawn.population import DrawnPopulation
    from linkcli.mechanisms.drawn.solver import Kinematics
    from linkcli.mechanisms.drawn.structure import Group, analyse
    drawing = _catalogue_drawing(label)
    structure = analyse(drawing)
    assert any(isinstance(op, Group) for op in structure.plan)
    names = tuple(j.name for j in drawing.joints)
    size = max(max(j.at[0] for j in drawing.joints) - min(j.at[0] for j in drawing.joints),
               max(j.at[1] for j in drawing.joints) - min(j.at[1] for j in drawing.joints))
    spread = 0.03 * size
    boxes = {n: ((x - spread, x + spread), (y - spread, y + spread)) for n, (x, y) in
             ((j.name, j.at) for j in drawing.joints)}
    pop = DrawnPopulation(drawing, structure, names, boxes, traced=names)
    rng = np.random.default_rng(11)
    x = pop.drawn[None, :] + rng.uniform(-spread, spread, (60, len(pop.drawn)))
    q = rng.uniform(-2 * math.pi, 2 * math.pi, (60, 40))
    motion = pop.kinematics(x, q)
    valid_rows = invalid_rows = 0
    for i in range(len(x)):
        design = pop.linkage(x[i])
        st = Kinematics(design, analyse(design)).run(q[i], rates=False)
        assert np.array_equal(motion.valid[i], st.valid), (i, np.flatnonzero(motion.valid[i] != st.valid))
        ok = st.valid
        valid_rows += int(ok.sum())
        invalid_rows += int((~ok).sum())
        places = {}
        for p, name in enumerate(names):
            np.testing.assert_allclose(motion.points[i, ok, p], st.pos[name][ok], atol=1e-8 * size, rtol=0)
            places[name] = motion.points[i, :, p]
        for drawn, found in _rigid_distances(design, places, ok):
            np.testing.assert_allclose(found, drawn, atol=1e-9 * size, rtol=0)
        margins = motion.margins[i][ok]
        assert np.all(margins >= 0.0)
    assert valid_rows > 400
    if "ternary" in label:  # its designs lock within the turn: rows past their dead points
        assert invalid_rows > 100


def test_triad_margins_vanish_at_the_dead_point_and_are_negative_past_it():
    """A design whose triad locks within the turn: the group's margin falls to 0 at the
    analysis's dead point (drawn.motion's reach) and is minus the turn past it, times the size."""
    from linkcli.mechanisms.drawn.population import DrawnPopulation
    from linkcli.mechanisms.drawn.solved import solved
    drawing = _catalogue_drawing("stephenson-ii, ternary crank (triad), tracer P on link")
    from dataclasses import replace
    moved = tuple(replace(j, at=(j.at[0] - 2.0, j.at[1] + 2.0)) if j.name == "E" else j for j in drawing.joints)
    design = replace(drawing, joints=moved)
    sv = solved(design)
    assert not sv.reach.full_turn  # a rocking crank: dead points at both ends
    pop = DrawnPopulation(design, sv.structure, (), {}, traced=("P",))
    hi = sv.reach.hi
    q = np.array([[hi - 1e-3, hi - 1e-6, hi + 1e-3, hi + 0.1]])
    motion = pop.kinematics(np.zeros((1, 0)), q)
    assert len(sv.structure.plan) == 2  # the crank, then the triad: every closure is the triad's
    m = motion.margins[0]
    assert list(motion.valid[0]) == [True, True, False, False]
    size = float(pop.size(np.zeros((1, 0)))[0])
    assert np.all(m[0] > m[1]) and np.all(m[1] >= 0) and np.all(m[1] < 1e-2 * size)
    np.testing.assert_allclose(m[2:], -size * (q[0, 2:, None] - hi) * np.ones((1, m.shape[1])), rtol=1e-3)


def _known_problem(seed: int, free: tuple[str, ...], n: int = 14, sigma: float = 2.0):
    """STEPHENSON_II's tracer P at n drive angles (the analysis's solver); the free joints then
    moved by a normal draw (sigma mm), each free within +-12 mm of its true place."""
    import tomllib

    from linkcli.mechanisms.drawn.solved import solved
    from linkcli.reading.load import load
    true = load("true.toml", STEPHENSON_II + '[target]\njoint = "P"\npoints = [[0, 0], [1, 1], [2, 0]]\n'
                'input_angles = [0, 1, 2]\n').drawing
    q = np.arange(n) * 2 * math.pi / n
    path = solved(true).kin.run(q, rates=False).pos["P"]
    assert np.isfinite(path).all()
    joints = tomllib.loads(STEPHENSON_II)["joints"]
    text = perturbed_problem(STEPHENSON_II, joints, free, path, q, seed, sigma) + "[solver]\nbudget = 20000\n"
    return text, path


@pytest.mark.slow
def test_a_known_stephenson_ii_is_recovered_from_a_perturbed_drawing():
    """Fourteen points of a Stephenson II's tracer (its triad driven by the crank), five joints
    free (10 coordinates), prescribed timing: on at least four of five seeds the search ends
    feasible at error ~0 (below 1e-6 of the path's extent; ok, or not-converged where the
    budget of 20,000 ends before a second round confirms it), and the designed drawing traces
    the points by the analysis's own solver too."""
    from linkcli.mechanisms.drawn.solved import solved
    from linkcli.pipeline import analyse, solve
    from linkcli.reading.load import load
    free = ("B", "C", "D", "E", "P")
    good = 0
    for seed in range(5):
        text, path = _known_problem(seed, free)
        problem = load("known.toml", text)
        solution = solve(problem)
        report = analyse(problem, solution)
        extent = float(np.ptp(path, axis=0).max())
        if report["status"] not in ("ok", "not-converged") or report["error"]["max"] > 1e-6 * extent:
            continue
        again = solved(solution.linkage).kin.run(np.asarray(solution.positions.input), rates=False).pos["P"]
        np.testing.assert_allclose(again, path, atol=1e-6 * extent)
        good += 1
    assert good >= 4


PATH = SWEEP_PATH.format(topology="stephenson-ii", target="", bounds="[solver]\nbudget = 8000\n")


@pytest.mark.slow
def test_the_stephenson_ii_topology_is_searched_and_analyze_takes_its_result(tmp_path):
    """topology = "stephenson-ii" (every choice a triad): every choice searched (no row left
    out), the chosen design's path through the analysis's solver is what the report prints,
    and `analyze` takes the result file as it is."""
    src = tmp_path / "s2.toml"
    src.write_text(PATH)
    code, out, err = run_cli("synth", str(src), "--format", "toml", "--precision", "15")
    assert code in (0, 1), err
    import tomllib
    report = tomllib.loads(out)
    rows = report["topologies"]["rows"]
    assert [r["topology"] for r in rows] == ["stephenson-ii"] * 4 + ["four-bar"]
    assert all(r["status"] in ("ok", "not-converged", "infeasible") for r in rows)
    result = tmp_path / "s2_result.toml"
    result.write_text(out)
    code, out2, err2 = run_cli("analyze", str(result), "--format", "json", "--precision", "15")
    assert code in (0, 1), err2
    again = json.loads(out2)
    assert again["linkage"]["joints"] == report["linkage"]["joints"]
    assert "group of 4" in json.dumps(again["grashof"]["groups"])  # the structure: the triad
    import tomli_w

    from linkcli.mechanisms.drawn.solved import solved
    from linkcli.reading.load import load
    lk = report["linkage"]  # the designed drawing, as an analysis file of its own
    joints = {k: {"at": v["at"], **({"ground": True} if v.get("ground") else {})} for k, v in lk["joints"].items()}
    design = load("design.toml", tomli_w.dumps({"type": "linkage", "linkage": {"mechanism": "drawn"}, "joints": joints,
                                                "links": lk["links"], "drive": {k: {} for k in lk["drive"]}})).linkage
    q = np.radians([p["input"] for p in report["positions"]])  # offsets from the drawn position
    sv = solved(design)
    places = sv.kin.run(np.mod(q, 2 * math.pi) if sv.reach.full_turn else q, rates=False).pos["P"]
    achieved = np.array([p["achieved"] for p in report["positions"]])
    np.testing.assert_allclose(places, achieved, atol=1e-6 * 40)


def _either_side_of_the_lock(apart: float):
    """Two Stephenson II designs `apart` (of E's box, in each coordinate) either side of the
    move of E where its crank stops turning (the analysis's reach, bisected): (turning,
    locking, the locking one's solved form, the population of E free in a box of +-10, x of a
    design)."""
    from dataclasses import replace

    from linkcli.mechanisms.drawn.population import DrawnPopulation
    from linkcli.mechanisms.drawn.solved import solved
    drawing = _catalogue_drawing("stephenson-ii, ternary crank (triad), tracer P on link")
    e0 = drawing.joint("E").at

    def moved(s):
        return replace(drawing, joints=tuple(replace(j, at=(e0[0] - s, e0[1] + s)) if j.name == "E" else j
                                             for j in drawing.joints))

    lo, hi = 0.8, 1.0  # turns fully at 0.8, locks at 1.0 (the analysis's reach)
    assert solved(moved(lo)).reach.full_turn and not solved(moved(hi)).reach.full_turn
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if solved(moved(mid)).reach.full_turn else (lo, mid)
    half = 10.0
    shift = 0.5 * apart * 2 * half
    turning, locking = moved(lo - shift), moved(lo + shift)
    sv = solved(locking)
    assert solved(turning).reach.full_turn and not sv.reach.full_turn
    box = {"E": ((e0[0] - half, e0[0] + half), (e0[1] - half, e0[1] + half))}

    def population():
        return DrawnPopulation(drawing, sv.structure, ("E",), box, traced=("P",))

    def design_x(d):
        return np.array([[d.joint("E").at[0], d.joint("E").at[1]]])

    return turning, locking, sv, population, design_x


def test_a_probe_with_a_dead_point_its_neighbour_lacks_follows_its_own_track():
    """A difference probe borrows the track of a design within NEAR of it (TrackCache.near).
    Two designs either side of the move of E where the Stephenson II's crank stops turning:
    the first turns fully, the second locks over a short stretch. Evaluated after the first, the
    second's rows in its locked stretch do not solve on the borrowed track; it then follows its
    own, and its margins -- negative past its dead point, nowhere undefined -- are those of the
    second design evaluated alone (the analysis's reach giving the dead point's place)."""
    from linkcli.mechanisms.drawn.population import NEAR
    turning, locking, sv, population, design_x = _either_side_of_the_lock(0.5 * NEAR)  # within NEAR
    q = np.linspace(0.0, 2 * math.pi, 4001)[None, :]

    alone = population().kinematics(design_x(locking), q)
    pop = population()
    pop.kinematics(design_x(turning), q)
    probed = pop.kinematics(design_x(locking), q)
    stuck = ~alone.valid[0]
    assert stuck.sum() > 5 and np.isfinite(alone.margins).all()
    assert np.array_equal(probed.valid, alone.valid)
    np.testing.assert_allclose(probed.margins, alone.margins, rtol=0, atol=1e-9)
    past = q[0, stuck] - sv.reach.hi  # past the dead point in the drive's direction
    size = float(pop.size(design_x(locking))[0])
    # the dead point to 1e-6 of a continuation step (10 deg): within 1e-6 rad of the analysis's
    np.testing.assert_allclose(probed.margins[0, stuck, 0], -size * past, rtol=0, atol=1e-6 * size)


@pytest.mark.parametrize("m", [1, 2, 3, 4, 6])
def test_the_populations_small_solves_are_lapacks(m):
    """population_groups.solve_small (lanes last: a (m, m, L), b (m, L)) -- Cramer's rule up to
    three unknowns, elimination with partial pivoting beyond -- against LAPACK's solve and
    determinant on 300 random systems, and Hadamard's ratio (_measure) against |det| over the
    product of the column norms; a singular system's determinant is 0 (to round-off beyond three
    unknowns)."""
    from linkcli.mechanisms.drawn.population_groups import _measure, det_small, solve_small
    rng = np.random.default_rng(m)
    a = rng.normal(size=(m, m, 300))
    b = rng.normal(size=(m, 300))
    stacked = a.transpose(2, 0, 1)
    x, det = solve_small(a, b)
    reference = np.linalg.solve(stacked, b.T[..., None])[..., 0].T
    cond = np.linalg.cond(stacked)
    assert np.all(np.abs(x - reference) <= 1e-13 * cond * (1.0 + np.abs(reference)))
    np.testing.assert_allclose(det, np.linalg.det(stacked), rtol=1e-11)
    assert np.array_equal(det_small(a), det)
    _, ratio = _measure(a, True)
    np.testing.assert_allclose(ratio, np.abs(det) / np.prod(np.linalg.norm(stacked, axis=1), axis=-1), rtol=1e-12)
    a[:, 0, :7] = a[:, 1, :7] if m > 1 else 0.0  # two equal columns (or a zero): singular
    x, det = solve_small(a, b)
    if m <= 3:  # the cofactors cancel exactly: no solution, determinant 0
        assert np.all(np.isnan(x[:, :7])) and np.all(det[:7] == 0.0)
    else:  # elimination leaves round-off in the last pivot
        assert np.all(np.abs(det[:7]) < 1e-12)


@pytest.mark.parametrize("label", ["stephenson-ii, ternary crank (triad), tracer P on link",
                                   "stephenson-iii, binary crank (triad), tracer P on link"])
def test_the_triads_real_residual_is_the_general_groups_and_its_jacobian_the_differences(label):
    """A six-bar's triad (one ternary link held by three lengths) is computed in real arithmetic
    (PopulationGroup._triad): at 500 random lanes (poses off the solution, known joints moved)
    its residual and Jacobian are the general group path's within round-off, and its Jacobian
    is the residual's central differences (h = 1e-6) within their truncation."""
    from linkcli.mechanisms.drawn.population import DrawnPopulation
    from linkcli.mechanisms.drawn.structure import Group, analyse
    drawing = _catalogue_drawing(label)
    structure = analyse(drawing)
    names = tuple(j.name for j in drawing.joints)
    boxes = {j.name: ((j.at[0] - 5, j.at[0] + 5), (j.at[1] - 5, j.at[1] + 5)) for j in drawing.joints}
    pop = DrawnPopulation(drawing, structure, names, boxes)
    index = next(i for i, op in enumerate(structure.plan) if isinstance(op, Group))
    group = pop.group_solver(index)
    assert group.triad is not None and group.m == 3
    rng = np.random.default_rng(5)
    n = 500
    x = pop.starts(rng, n)
    z0 = pop.places(x)
    lanes = np.arange(n)
    z = group.drawn(z0, lanes) + rng.normal(size=(n, 3)) * [3.0, 3.0, 0.5]
    known = group.stack_known({j: z0[j][:, 0] + 2.0 * (rng.normal(size=n) + 1j * rng.normal(size=n))
                               for j in group.known}, n)
    f, jac = group.residual(z, known, group.constants(z0, lanes))
    shape = group.triad
    group.triad = None  # the general path: complex places, the Jacobian's pattern tables
    try:
        const = group.constants(z0, lanes)
        f_general, jac_general = group.residual(z, known, const)
    finally:
        group.triad = shape
    size = float(np.max(pop.size(x)))
    np.testing.assert_allclose(f, f_general, rtol=0, atol=1e-12 * size)
    np.testing.assert_allclose(jac, jac_general, rtol=0, atol=1e-12 * size)
    h = 1e-6
    const = group.constants(z0, lanes)
    for c in range(3):
        step = np.zeros(3)
        step[c] = h
        hi, _ = group.residual(z + step, known, const, jacobian=False)
        lo, _ = group.residual(z - step, known, const, jacobian=False)
        np.testing.assert_allclose(jac[:, :, c], (hi - lo) / (2 * h), rtol=1e-6, atol=1e-6)
    places = group.places(z, known, const)
    assert set(places) == {group.ends[e][0] for e in shape[0]}
    for e in shape[0]:  # a pin on the ternary: its hub plus its drawn arm turned by theta
        joint = group.ends[e][0]
        arm = (z0[joint][:, 0] - z0[group.anchor[group.kept[0]]][:, 0]) * np.exp(1j * z[:, 2])
        np.testing.assert_allclose(places[joint], z[:, 0] + 1j * z[:, 1] + arm, rtol=0, atol=1e-12 * size)


def _triad_population(label, spread_of_size=0.03, traced=("P",)):
    from linkcli.mechanisms.drawn.population import DrawnPopulation
    from linkcli.mechanisms.drawn.structure import analyse
    drawing = _catalogue_drawing(label)
    size = max(max(j.at[0] for j in drawing.joints) - min(j.at[0] for j in drawing.joints),
               max(j.at[1] for j in drawing.joints) - min(j.at[1] for j in drawing.joints))
    spread = spread_of_size * size
    boxes = {j.name: ((j.at[0] - spread, j.at[0] + spread), (j.at[1] - spread, j.at[1] + spread))
             for j in drawing.joints}
    names = tuple(j.name for j in drawing.joints)
    return lambda: DrawnPopulation(drawing, analyse(drawing), names, boxes, traced=traced), size


def _counting(monkeypatch, name):
    """Count the designs population_groups.`name` is called for."""
    from linkcli.mechanisms.drawn import population_groups as pg
    calls = []
    real = getattr(pg, name)

    def wrapped(group, prefix, z0, scale, *rest):
        calls.append(len(scale))
        return real(group, prefix, z0, scale, *rest)
    monkeypatch.setattr(pg, name, wrapped)
    return calls


@pytest.mark.parametrize("label", ["stephenson-ii, binary crank (triad), tracer P on coupler",
                                   "stephenson-iii, binary crank (triad), tracer P on link"])
def test_tracks_carried_from_near_designs_give_the_followed_rows(label, monkeypatch):
    """A design within CARRY of one the population has followed has its track carried over
    (population_groups.transport: Newton at the neighbour's nodes) instead of followed: its
    rows -- validity, places, margins -- are those of the same designs evaluated afresh, and
    validity and places the analysis's solver's (drawn.solver with drawn.groups: twelve
    unknowns, its own continuation), row for row."""
    from linkcli.mechanisms.drawn import population_groups as pg
    from linkcli.mechanisms.drawn.population import CARRY
    from linkcli.mechanisms.drawn.solver import Kinematics
    from linkcli.mechanisms.drawn.structure import analyse
    make, size = _triad_population(label)
    carried = []
    real = pg.transport

    def counted(*args):
        track, ok = real(*args)
        carried.append(int(ok.sum()))
        return track, ok
    monkeypatch.setattr(pg, "transport", counted)
    pop = make()
    rng = np.random.default_rng(3)
    base = pop.drawn[None, :] + rng.uniform(-0.5, 0.5, (12, len(pop.drawn))) * (pop.hi - pop.lo) * 0.2
    q = np.repeat(np.linspace(0.0, 2 * math.pi, 48, endpoint=False)[None, :], len(base), axis=0)
    first = pop.kinematics(base, q)
    moved = base + rng.uniform(-0.5, 0.5, base.shape) * CARRY * (pop.hi - pop.lo)
    again = pop.kinematics(moved, q)
    assert first.valid.all() and sum(carried) >= len(base) - 2, carried  # all 12 on this machine
    fresh = make().kinematics(moved, q)
    assert np.array_equal(again.valid, fresh.valid) and fresh.valid.mean() > 0.5
    ok = fresh.valid
    np.testing.assert_allclose(again.points[ok], fresh.points[ok], rtol=0, atol=1e-9 * size)
    np.testing.assert_allclose(again.margins[ok], fresh.margins[ok], rtol=0, atol=1e-9 * size)
    for i in range(len(moved)):
        design = pop.linkage(moved[i])
        st = Kinematics(design, analyse(design)).run(q[i], rates=False)
        assert np.array_equal(again.valid[i], st.valid), i
        for p, name in enumerate(pop.traced):
            np.testing.assert_allclose(again.points[i, st.valid, p], st.pos[name][st.valid], atol=1e-8 * size, rtol=0)


def test_a_design_with_a_dead_point_its_neighbour_lacks_is_followed_not_carried(monkeypatch):
    """Two Stephenson II designs either side of the move of E where the crank stops turning,
    farther apart than a difference probe (NEAR) but within CARRY: the second's track is not
    carried from the first's (the nodes past its dead point do not solve on its drawn branch):
    it is followed, and its margins -- negative past the dead point -- are those of the design
    evaluated alone."""
    from linkcli.mechanisms.drawn.population import CARRY, NEAR
    turning, locking, sv, population, design_x = _either_side_of_the_lock(0.5 * (NEAR + CARRY))
    q = np.linspace(0.0, 2 * math.pi, 721)[None, :]

    alone = population().kinematics(design_x(locking), q)
    followed = _counting(monkeypatch, "follow")
    tried = _counting(monkeypatch, "transport")
    pop = population()
    pop.kinematics(design_x(turning), q)
    second = pop.kinematics(design_x(locking), q)
    assert tried == [1] and followed == [1, 1]
    assert (~alone.valid).sum() > 5
    assert np.array_equal(second.valid, alone.valid)
    np.testing.assert_allclose(second.margins, alone.margins, rtol=0, atol=1e-9)


def test_a_closed_branch_serves_any_drive_value_and_a_design_is_followed_once_a_call(monkeypatch):
    """A design whose crank turns fully (its track periodic) gives at q - 2 pi and q + 4 pi the
    rows it gives at q, from the track it followed once; a call holding one design several
    times (a search's constraints of one candidate) follows it once."""
    make, size = _triad_population("stephenson-ii, binary crank (triad), tracer P on coupler", spread_of_size=0.0)
    followed = _counting(monkeypatch, "follow")
    pop = make()
    x = np.repeat(pop.drawn[None, :], 3, axis=0)
    q = np.repeat(np.linspace(0.1, 2 * math.pi - 0.1, 30)[None, :], 3, axis=0)
    one = pop.kinematics(x, q)
    assert followed == [1] and one.valid.all()
    back = pop.kinematics(x[:1], q[:1] - 2 * math.pi)
    ahead = pop.kinematics(x[:1], q[:1] + 4 * math.pi)
    assert followed == [1]
    for other in (back, ahead):
        assert other.valid.all()
        np.testing.assert_allclose(other.points[0], one.points[0], rtol=0, atol=1e-9 * size)
    np.testing.assert_array_equal(one.points[1], one.points[0])


def test_rows_at_a_triads_dead_point_have_a_margin_where_they_do_not_solve():
    """Designs around a triad drawing that locks within the turn, rows within 1e-6 rad either
    side of each one's dead point as the analysis places it (drawn.solved: to 1e-12 of a step):
    every row has a finite margin (a row there that does not solve is at the dead point within
    the track's accuracy: 0, not NaN, which the search would read as far infeasible), within
    1e-2 of the size of 0, and past the dead point by more than the band, minus the travel."""
    from dataclasses import replace

    from linkcli.mechanisms.drawn.population import DrawnPopulation
    from linkcli.mechanisms.drawn.solved import solved
    drawing = _catalogue_drawing("stephenson-ii, ternary crank (triad), tracer P on link")
    names = tuple(j.name for j in drawing.joints if not j.ground)
    rng = np.random.default_rng(5)
    his, xs = [], []
    for _ in range(40):
        moved = tuple(replace(j, at=(j.at[0] + rng.uniform(-4, 4), j.at[1] + rng.uniform(-4, 4)))
                      if not j.ground else j for j in drawing.joints)
        sv = solved(replace(drawing, joints=moved))
        if sv.reach.full_turn:  # a crank: no dead point
            continue
        his.append(sv.reach.hi)
        xs.append([c for j in moved if not j.ground for c in j.at])
    assert len(his) >= 20  # 27 of the 40 draws rock
    boxes = {j.name: ((j.at[0] - 10, j.at[0] + 10), (j.at[1] - 10, j.at[1] + 10)) for j in drawing.joints
             if not j.ground}
    pop = DrawnPopulation(drawing, solved(drawing).structure, names, boxes, traced=("P",))
    x, hi = np.array(xs), np.array(his)
    offsets = np.array([-1e-6, -3e-7, -1e-7, -3e-8, -1e-8, 0.0, 1e-8, 1e-7, 1e-6, 1e-3])
    motion = pop.kinematics(x, hi[:, None] + offsets[None, :])
    size = pop.size(x)[:, None, None]
    m = motion.margins
    assert np.all(np.isfinite(m))
    assert np.all(np.abs(m[:, :-1]) < 1e-2 * size)
    np.testing.assert_allclose(m[:, -1], -size[:, 0] * 1e-3 * np.ones(m.shape[::2]), rtol=1e-2)


def test_a_drawing_with_a_triad_has_a_tenth_of_the_default_budget(monkeypatch):
    """Without [solver] budget, a design whose plan has a group followed by continuation (a
    triad: an evaluation some ten times a dyad's) gets DEFAULT_BUDGET / GROUP_COST evaluations,
    a plan of dyads DEFAULT_BUDGET, free timing through 40 points half of it (20 / 40: each
    point a timing variable); a budget given is the budget (the search itself stubbed: only the
    budget it is handed is looked at)."""
    from linkcli.mechanisms.drawn.population import GROUP_COST
    from linkcli.pipeline import solve
    from linkcli.reading.load import load
    from linkcli.synthesis import search as shared
    handed = []

    def search(model, budget, rng):
        handed.append(budget.total)
        return [], False

    monkeypatch.setattr(shared, "search", search)
    text, _ = _known_problem(0, ("B", "C"))
    triad = text.replace("[solver]\nbudget = 20000\n", "")
    dyads = (ROOT / "problems" / "drawn_dwell.toml").read_text()  # Stephenson III: crank, then two dyads
    assert "[solver]" not in dyads
    stride = (ROOT / "problems" / "drawn_jansen_stride.toml").read_text()  # free timing, 14 points
    start, end = stride.index("points = ["), stride.index('timing = "free"')
    ring = [[round(30 * math.cos(t), 6), round(-72.5 + 12.5 * math.sin(t), 6)]
            for t in np.arange(40) * 2 * math.pi / 40]
    many = stride[:start] + f"points = {ring}\n" + stride[end:]  # 40 points: 20 / 40 of the budget
    for body, total in ((triad, shared.DEFAULT_BUDGET // GROUP_COST), (text, 20000), (dyads, shared.DEFAULT_BUDGET),
                        (stride, shared.DEFAULT_BUDGET), (many, shared.DEFAULT_BUDGET // 2)):
        solve(load("t.toml", body))
        assert handed[-1] == total
    assert GROUP_COST == 10 and shared.FREE_TARGETS == 20
