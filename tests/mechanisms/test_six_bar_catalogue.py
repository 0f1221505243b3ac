"""The six-bar catalogue (docs/six_bars.md, issue 49 point 3).

- Counts against an enumeration written here: every multigraph of n links and (3 n - 4) / 2
  pins (double pins included), kept when connected and every sub-chain moves by Gruebler's
  count, one per isomorphism class found by trying all n! relabellings; the literature's
  counts (1 four-bar chain and inversion; 2 six-bar chains, Watt's and Stephenson's, and 5
  inversions: Hartenberg & Denavit, Tsai) and the catalogue's drives and targets as orbits
  of (ground, drive, target) under the automorphisms, classified by the four-link sub-chains
  that move by themselves (Gruebler mobility 1).
- Every starting drawing through linkcli's own structure analysis and drawn motion solver:
  no structural problem, the crank turns fully (motion.reach), every closure it measures
  within [30, 150] deg (1 deg of slack between the construction's 360 rows), no link faster
  than 10 times the crank (no near-dead point), the tracer's path filling the box; readable
  from a TOML file written by `to_tables`.
- A tracer whose timing alone is the six-bar's ("prescribed") draws a curve of the four-bar
  loop that holds it with the ground: checked against that four-bar's whole coupler curve,
  sampled here from the drawing's lengths, before and after the crank is changed.
- The same drawings for a seed, in this process and with numpy's vector paths disabled.
- `[linkage] topology`: every value, and its bad inputs as one located line each.
"""

from __future__ import annotations

import math
import os
import re
import subprocess
import sys
from collections import Counter
from functools import lru_cache
from itertools import combinations, combinations_with_replacement, permutations

import numpy as np
import pytest
import tomli_w
from conftest import ROOT

from linkcli.errors import InputErrors
from linkcli.io.reader import Reader
from linkcli.mechanisms.drawn import catalogue, chains
from linkcli.mechanisms.drawn.motion import closure_vectors, reach, transmission
from linkcli.mechanisms.drawn.solver import Kinematics
from linkcli.mechanisms.drawn.structure import analyse
from linkcli.mechanisms.drawn.topology import TOPOLOGIES, read_topology, topologies
from linkcli.reading.load import load

SIX = ("watt-i", "watt-ii", "stephenson-i", "stephenson-ii", "stephenson-iii")
BOX = (-30.0, 10.0, 70.0, 50.0)  # x_lo, y_lo, x_hi, y_hi: 100 x 40, off the origin


# ---------------------------------------------------------------- the enumeration, written here

def gruebler(links: int, pins: int) -> int:
    return 3 * (links - 1) - 2 * pins


def relabel(edges, label) -> tuple:
    return tuple(sorted(tuple(sorted((label[a], label[b]))) for a, b in edges))


def movable(n: int, edges) -> bool:
    """Connected, and every set of 2 .. n - 1 links with its pins moves (mobility >= 1)."""
    seen, todo = {0}, [0]
    while todo:
        v = todo.pop()
        for a, b in edges:
            for x, y in ((a, b), (b, a)):
                if x == v and y not in seen:
                    seen.add(y)
                    todo.append(y)
    if len(seen) < n:
        return False
    for size in range(2, n):
        for subset in combinations(range(n), size):
            if gruebler(size, sum(1 for a, b in edges if a in subset and b in subset)) < 1:
                return False
    return True


@lru_cache(maxsize=2)
def brute_chains(n: int) -> tuple:
    """One edge list (a multigraph: a double pin would be two equal edges) per class of
    1-dof chains of n links."""
    pins = (3 * n - 4) // 2
    relabellings = list(permutations(range(n)))
    known: set = set()
    reps = []
    for edges in combinations_with_replacement(list(combinations(range(n), 2)), pins):
        degree = Counter(v for e in edges for v in e)
        if len(degree) < n or min(degree.values()) < 2:
            continue  # a link on one pin: the others are rigid (movable would say so, slower)
        if edges in known or not movable(n, edges):
            continue
        known |= {relabel(edges, p) for p in relabellings}
        reps.append(edges)
    return tuple(reps)


def automorphisms(n: int, edges) -> list:
    return [p for p in permutations(range(n)) if relabel(edges, p) == tuple(sorted(edges))]


def neighbours(edges, v) -> set:
    return {b if a == v else a for a, b in edges if v in (a, b)}


def literature_name(n: int, edges, ground: int) -> str:
    """Watt's chain has its two ternary links pinned together, Stephenson's apart; Watt II and
    Stephenson III ground a ternary link; Stephenson I grounds the binary link pinned to both
    ternary links (both pivot on the ground), Stephenson II a binary link pinned to one."""
    if n == 4:
        return "four-bar"
    degree = Counter(v for e in edges for v in e)
    ternary = [v for v in range(n) if degree[v] == 3]
    if tuple(sorted(ternary)) in edges:
        return "watt-ii" if degree[ground] == 3 else "watt-i"
    if degree[ground] == 3:
        return "stephenson-iii"
    return "stephenson-i" if len(neighbours(edges, ground) & set(ternary)) == 2 else "stephenson-ii"


def moves_alone(n: int, edges, members) -> bool:
    """Some four links holding `members` move by themselves: 4 pins among them (mobility 1)."""
    return any(set(members) <= set(s) and gruebler(4, sum(1 for a, b in edges if a in s and b in s)) == 1
               for s in combinations(range(n), 4))


def orbits(group, items) -> list:
    return sorted({min(tuple(p[v] for v in item) for p in group) for item in items})


@lru_cache(maxsize=2)
def brute_counts(n: int) -> dict:
    """name -> counts: drives (binary ones), path/motion targets beyond the four-bar with free
    timing ("any"), only with prescribed timing, moved by a four-bar with the drive
    ("four-bar"), function outputs and those a four-bar with the drive does not move alone."""
    out: dict = {}
    for edges in brute_chains(n):
        group = automorphisms(n, edges)
        for (g,) in orbits(group, [(v,) for v in range(n)]):
            name = literature_name(n, edges, g)
            row = out.setdefault(name, Counter())
            row["inversions"] += 1
            pairs = [(g, k) for k in neighbours(edges, g)]
            stab = [p for p in group if p[g] == g]
            for _, k in orbits(stab, pairs):
                row["drives"] += 1
                row["binary drives"] += len(neighbours(edges, k)) == 2
                fix = [p for p in stab if p[k] == k]
                floating = [(t,) for t in range(n) if t != g and t not in neighbours(edges, g)]
                for (t,) in orbits(fix, floating):
                    if n > 4 and moves_alone(n, edges, (g, k, t)):
                        row["four-bar"] += 1
                    elif n > 4 and moves_alone(n, edges, (g, t)):
                        row["prescribed"] += 1
                    else:
                        row["any"] += 1
                outputs = [(o,) for o in neighbours(edges, g) if o != k]
                for (o,) in orbits(fix, outputs):
                    row["outputs"] += 1
                    row["six-bar outputs"] += not (n > 4 and moves_alone(n, edges, (g, k, o)))
    return out


# ---------------------------------------------------------------- counts

def test_the_brute_force_finds_the_literatures_chains_and_inversions():
    """Tsai (2001): one 1-dof chain of four links, two of six (Watt, Stephenson; the chain
    with a quaternary link holds a rigid triangle); Hartenberg & Denavit: five inversions."""
    assert len(brute_chains(4)) == 1
    six = brute_chains(6)
    assert len(six) == 2
    degrees = [sorted(Counter(v for e in edges for v in e).values()) for edges in six]
    assert degrees == [[2, 2, 2, 2, 3, 3]] * 2
    assert all(len(set(edges)) == len(edges) for edges in six)  # double pins are rigid: none left
    names = {literature_name(6, edges, g) for edges in six for g in range(6)}
    assert names == set(SIX)
    assert sum(row["inversions"] for row in brute_counts(6).values()) == 5
    assert all(row["inversions"] == 1 for row in brute_counts(6).values())


def test_the_modules_chains_are_the_brute_forces():
    for n in (4, 6):
        found = chains.chains(n)
        assert len(found) == len(brute_chains(n))
        for chain in found:
            assert chains.is_chain(n, chain.edges) and movable(n, chain.edges)
            assert any(relabel(chain.edges, p) == tuple(sorted(rep)) for rep in brute_chains(n)
                       for p in permutations(range(n)))
        assert [c.name for c in chains.chains(6)] == ["watt", "stephenson"]
    with pytest.raises(ValueError):
        chains.chains(5)


def test_the_modules_inversions_drives_and_targets_are_the_brute_forces():
    module = {}
    for n in (4, 6):
        for inv in chains.inversions(n):
            assert inv.name == literature_name(n, inv.chain.edges, inv.ground)
            row = module.setdefault(inv.name, Counter())
            row["inversions"] += 1
            for k in inv.drives():
                row["drives"] += 1
                row["binary drives"] += inv.chain.degree(k) == 2
                targets = inv.targets(k, "path")
                assert targets == inv.targets(k, "motion")
                row["any"] += sum(1 for _, timing in targets if timing == "any")
                row["prescribed"] += sum(1 for _, timing in targets if timing == "prescribed")
                row["six-bar outputs"] += len(inv.targets(k, "function"))
    brute = {**brute_counts(4), **brute_counts(6)}
    keys = ("inversions", "drives", "binary drives", "any", "prescribed", "six-bar outputs")
    assert {name: {k: module[name][k] for k in keys} for name in module} == \
        {name: {k: brute[name][k] for k in keys} for name in brute}


def documented_table() -> dict:
    """The counts table of docs/six_bars.md: inversion -> its numbers."""
    text = (ROOT / "docs" / "six_bars.md").read_text(encoding="utf-8")
    head = text.index("| inversion | drives |")
    rows = text[head:text.index("\n\n", head)].splitlines()
    columns = [c.strip() for c in rows[0].strip("|").split("|")]
    out = {}
    for line in rows[2:]:
        cells = [c.strip().strip("`*") for c in line.strip("|").split("|")]
        out[cells[0]] = dict(zip(columns[1:], (int(re.match(r"\d+", c).group()) for c in cells[1:])))
    return out


def test_the_documented_counts_are_the_brute_forces():
    table = documented_table()
    brute = {**brute_counts(4), **brute_counts(6)}
    for name in SIX + ("four-bar",):
        row = brute[name]
        assert table[name] == {"drives": row["drives"], "binary drives": row["binary drives"],
                               "targets": row["any"] + row["prescribed"] + row["four-bar"],
                               "any timing": row["any"], "prescribed timing": row["prescribed"],
                               "outputs": row["outputs"], "six-bar outputs": row["six-bar outputs"]}, name
    total = table["all six-bars"]
    for column in total:
        assert total[column] == sum(table[name][column] for name in SIX), column
    assert total == {"drives": 9, "binary drives": 5, "targets": 20, "any timing": 12,
                     "prescribed timing": 2, "outputs": 11, "six-bar outputs": 5}


def test_the_catalogue_offers_each_choice_once_with_a_unique_label():
    for task in catalogue.TASKS:
        every = catalogue.choices("any six-bar", task)
        assert len({c.label for c in every}) == len(every)
        assert [c.topology for c in every] == sorted((c.topology for c in every), key=SIX.index)
        free = catalogue.choices("any six-bar", task, timing="any")
        if task == "function":
            assert free == every  # timed by nature
        else:
            assert set(free) < set(every) and all(c.timing == "any" for c in free)
    assert len(catalogue.choices("any six-bar", "path")) == 14
    assert len(catalogue.choices("any six-bar", "path", "any")) == 12
    assert len(catalogue.choices("any six-bar", "function")) == 5
    assert len(catalogue.choices("four-bar", "path")) == len(catalogue.choices("four-bar", "function")) == 1
    assert catalogue.choices("watt-ii", "path", "any") == ()
    assert "four-bar's" in catalogue.empty_reason("watt-ii", "path", "any")
    assert "four-bar's" in catalogue.empty_reason("watt-i", "function")
    assert catalogue.empty_reason("stephenson-ii", "function") is None
    with pytest.raises(ValueError):
        catalogue.choices("watt-iii", "path")


# ---------------------------------------------------------------- the starting drawings

CHOICES = [c for task in catalogue.TASKS for name in SIX + ("four-bar",) for c in catalogue.choices(name, task)]


def solved(drawing, rows: int = 721):
    structure = analyse(drawing)
    assert not structure.problems, structure.problems
    kin = Kinematics(drawing, structure)
    assert reach(kin).full_turn
    state = kin.run(np.linspace(0.0, 2.0 * math.pi, rows), rates=True)
    assert state.valid.all()
    return structure, kin, state


def box_of(points: np.ndarray) -> tuple:
    return points[:, 0].min(), points[:, 1].min(), points[:, 0].max(), points[:, 1].max()


@pytest.mark.parametrize("choice", CHOICES, ids=lambda c: f"{c.task}: {c.label}")
def test_every_starting_drawing_turns_fully_with_its_closures_open(choice):
    seeds = (0, 1) if choice.task != "motion" else (2,)
    for seed in seeds:
        for drawing in catalogue.starting_drawings(choice, BOX, seed=seed, count=2):
            structure, kin, state = solved(drawing)
            for closure in structure.closures():
                mu = np.degrees(transmission(closure.kind, *closure_vectors(kin, state, closure))[0])
                assert 29.0 <= mu.min() and mu.max() <= 151.0, (seed, closure, mu.min(), mu.max())
            fastest = max(np.abs(state.omega[link.name]).max() for link in drawing.links)
            assert fastest <= 10.0 * drawing.drives[0].speed
            names = {link.name: link.joints for link in drawing.links}
            assert drawing.drives[0].name == "crank" == choice.drive
            grounded = [j.name for j in drawing.joints if j.ground]
            assert grounded == [f"O{k}" for k in range(1, len(grounded) + 1)]
            assert names["crank"][0] == "O1"
            x_lo, y_lo, x_hi, y_hi = BOX
            size = max(x_hi - x_lo, y_hi - y_lo)
            if choice.task == "function":
                assert drawing.output == "output" == choice.target
                swept = np.concatenate([state.pos[j.name] for j in drawing.joints])
                lo_x, lo_y, hi_x, hi_y = box_of(swept)
            else:
                assert "P" in names[choice.target] and drawing.points == ("P",)
                if choice.task == "motion":
                    assert names[choice.target][:2] == ("P", "Q")
                lo_x, lo_y, hi_x, hi_y = box_of(state.pos["P"])
            slack = 2e-3 * size
            assert x_lo - slack <= lo_x and hi_x <= x_hi + slack and y_lo - slack <= lo_y and hi_y <= y_hi + slack
            fill = max((hi_x - lo_x) / max(x_hi - x_lo, 0.2 * size), (hi_y - lo_y) / max(y_hi - y_lo, 0.2 * size))
            assert fill >= 0.98


@pytest.mark.parametrize("choice", [c for c in CHOICES if c.task != "motion"], ids=lambda c: f"{c.task}: {c.label}")
def test_a_starting_drawing_reads_back_from_its_toml_tables(choice, tmp_path):
    drawing = catalogue.starting_drawings(choice, BOX, seed=4, count=1)[0]
    document = {"type": "linkage", "linkage": {"mechanism": "drawn"}, **catalogue.to_tables(drawing),
                "motion": {"steps": 36}}
    path = tmp_path / "start.toml"
    path.write_text(tomli_w.dumps(document), encoding="utf-8")
    problem = load(str(path))
    assert problem.linkage.joints == drawing.joints
    assert problem.linkage.links == drawing.links


def test_the_drawings_are_the_same_for_a_seed_and_differ_between_seeds():
    for choice in (catalogue.choices("watt-i", "path")[0], catalogue.choices("stephenson-ii", "path")[0],
                   catalogue.choices("stephenson-ii", "function")[1]):
        first = catalogue.starting_drawings(choice, BOX, seed=7, count=3)
        assert catalogue.starting_drawings(choice, BOX, seed=7, count=3) == first
        assert catalogue.starting_drawings(choice, BOX, seed=7, count=1) == first[:1]  # each its own stream
        assert len({d.joints for d in first}) == 3
        other = catalogue.starting_drawings(choice, BOX, seed=8, count=1)[0]
        assert other.joints != first[0].joints and other.links == first[0].links  # names stay
    with pytest.raises(ValueError):
        catalogue.starting_drawings(choice, (0, 0, 0, 0))


def cpu_features_off() -> dict | None:
    try:
        from numpy._core._multiarray_umath import __cpu_dispatch__ as dispatch
        from numpy._core._multiarray_umath import __cpu_features__ as features
    except ImportError:
        return None
    enabled = [f for f in dispatch if features.get(f)]
    return {**os.environ, "NPY_DISABLE_CPU_FEATURES": ",".join(enabled)} if enabled else None


PRINT = """
from linkcli.mechanisms.drawn import catalogue
for task in ("path", "function"):
    for choice in catalogue.choices("any six-bar", task):
        print(choice.label, catalogue.starting_drawings(choice, (-30.0, 10.0, 70.0, 50.0), seed=3, count=1))
"""


def test_the_drawings_are_the_same_with_numpys_vector_paths_disabled():
    env = cpu_features_off()
    if env is None:
        pytest.skip("numpy runs its baseline vector paths already")
    here = subprocess.run([sys.executable, "-c", PRINT], capture_output=True, text=True, cwd=ROOT, timeout=600,
                          check=False)
    there = subprocess.run([sys.executable, "-c", PRINT], capture_output=True, text=True, cwd=ROOT, timeout=600,
                           env=env, check=False)
    assert here.returncode == 0 and there.returncode == 0, here.stderr + there.stderr
    assert here.stdout == there.stdout


# ---------------------------------------------------------------- a tracer whose timing alone is the six-bar's

def holders(drawing, target: str) -> list:
    """(ground pivot, pin on the target) of each link but the crank pinned both to the ground
    and to the target link."""
    ground = {j.name for j in drawing.joints if j.ground}
    links = {k.name: k.joints for k in drawing.links}
    return [(next(j for j in joints if j in ground), next(j for j in joints if j in links[target]))
            for name, joints in links.items()
            if name not in (target, "crank") and set(joints) & ground and set(joints) & set(links[target])]


def four_bar_curve(drawing, target: str, samples: int = 20000) -> tuple:
    """The chords (starts, ends) of P's whole curve on the four-bar of the ground and the two
    pivoted links that hold the target link (both assembly branches), from the drawing's
    lengths: sampled over the angle of each of the two, so that the other's toggles leave no
    gap."""
    at = {j.name: np.array(j.at) for j in drawing.joints}
    pair = holders(drawing, target)
    assert len(pair) == 2, pair
    parts = coupler_curve(at, *pair[0], *pair[1], samples) + coupler_curve(at, *pair[1], *pair[0], samples)
    return np.concatenate([p for p, _ in parts]), np.concatenate([q for _, q in parts])


def coupler_curve(at: dict, oa: str, a: str, ob: str, b: str, samples: int) -> list:
    """Chords of P's places on the four-bar oa-a-b-ob (lengths and P's place on a-b as drawn)
    over the angle of oa-a, one list entry per branch."""
    la, lb = np.linalg.norm(at[a] - at[oa]), np.linalg.norm(at[b] - at[ob])
    lab = np.linalg.norm(at[b] - at[a])
    u, r = at[b] - at[a], at["P"] - at[a]
    local = np.array([u @ r, u[0] * r[1] - u[1] * r[0]]) / (lab * lab)
    psi = np.linspace(0.0, 2.0 * math.pi, samples, endpoint=False)
    pa = at[oa] + la * np.stack([np.cos(psi), np.sin(psi)], axis=1)
    d = at[ob] - pa
    rho = np.linalg.norm(d, axis=1)
    e = d / rho[:, None]
    along = (lab ** 2 - lb ** 2 + rho ** 2) / (2.0 * rho)
    ok = np.abs(along) <= lab
    across = np.sqrt(np.where(ok, lab ** 2 - along ** 2, 0.0))
    joined = ok & np.roll(ok, -1)  # a chord joins two places that both exist
    out = []
    for side in (1.0, -1.0):
        pb = pa + along[:, None] * e + side * across[:, None] * np.stack([-e[:, 1], e[:, 0]], axis=1)
        w = pb - pa
        p = pa + local[0] * w + local[1] * np.stack([-w[:, 1], w[:, 0]], axis=1)
        out.append((p[joined], np.roll(p, -1, axis=0)[joined]))
    return out


def farthest_from(curve: tuple, points: np.ndarray) -> float:
    """The largest distance of the points from the chords of a curve."""
    start, end = curve
    chord = end - start
    length2 = np.maximum((chord * chord).sum(axis=1), 1e-300)
    worst = 0.0
    for point in points:
        t = np.clip(((point - start) * chord).sum(axis=1) / length2, 0.0, 1.0)
        gap = point - start - t[:, None] * chord
        worst = max(worst, float(np.sqrt((gap * gap).sum(axis=1).min())))
    return worst


@pytest.mark.parametrize("choice", [c for c in catalogue.choices("any six-bar", "path") if c.timing == "prescribed"],
                         ids=lambda c: c.label)
def test_a_prescribed_timing_tracer_draws_its_four_bars_curve_whatever_the_crank(choice):
    drawing = catalogue.starting_drawings(choice, BOX, seed=5, count=1)[0]
    curve = four_bar_curve(drawing, choice.target)
    tolerance = 1e-5 * (BOX[2] - BOX[0])  # the chords' sag: 2e-8 of the box or less here
    _, _, state = solved(drawing, rows=361)
    assert farthest_from(curve, state.pos["P"]) <= tolerance
    # the check has teeth: a holder's pivot moved by 2 % of the box moves the curve off by more
    pivot = holders(drawing, choice.target)[1][0]
    shifted = tuple(type(j)(j.name, (j.at[0] + 0.02 * (BOX[2] - BOX[0]), j.at[1]), j.ground) if j.name == pivot
                    else j for j in drawing.joints)
    _, _, state3 = solved(type(drawing)(joints=shifted, links=drawing.links, drives=drawing.drives,
                                        points=drawing.points), rows=361)
    assert farthest_from(curve, state3.pos["P"]) > 10.0 * tolerance
    # another crank (its pins moved 2 % out from O1; the links pinned there change length)
    crank = next(k for k in drawing.links if k.name == "crank")
    o1 = np.array(drawing.joint("O1").at)
    moved = tuple(type(j)(j.name, tuple(o1 + 1.02 * (np.array(j.at) - o1)), j.ground) if j.name in crank.joints[1:]
                  else j for j in drawing.joints)
    other = type(drawing)(joints=moved, links=drawing.links, drives=drawing.drives, points=drawing.points)
    _, _, state2 = solved(other, rows=361)
    assert np.abs(state2.pos["P"] - state.pos["P"]).max() > 1e-3 * (BOX[2] - BOX[0])  # other timing
    assert farthest_from(curve, state2.pos["P"]) <= tolerance  # the same curve
    # an "any" tracer of the same crank has no four-bar of the ground holding its link
    for free in catalogue.choices(choice.topology, "path", "any"):
        assert len(holders(catalogue.starting_drawings(free, BOX, seed=5, count=1)[0], free.target)) < 2


# ---------------------------------------------------------------- [linkage] topology

def read(text: str):
    """(value, error lines) of `read_topology` on a file's [linkage]."""
    reader = Reader("f.toml", text)
    root = reader.root()
    root.raw("type")
    linkage = root.table("linkage")
    linkage.raw("mechanism")
    value = read_topology(linkage)
    try:
        reader.finish()
    except InputErrors as exc:
        return value, exc.lines()
    return value, []


HEAD = 'type = "path-generation"\n[linkage]\nmechanism = "drawn"\n'


@pytest.mark.parametrize("value", TOPOLOGIES)
def test_every_topology_is_read(value):
    assert read(HEAD + f'topology = "{value}"\n') == (value, [])
    assert set(topologies(value)) <= set(SIX)
    assert topologies(value) == (SIX if value == "any six-bar" else (value,))
    assert {c.topology for c in catalogue.choices(value, "path")} == set(topologies(value))


def test_without_topology_nothing_is_read():
    assert read(HEAD) == (None, [])


BAD_TOPOLOGY = {
    '"Watt 2"': ' (did you mean "watt-ii"?), found "Watt 2" (string)',
    '"stephenson3"': ' (did you mean "stephenson-iii"?), found "stephenson3" (string)',
    '"Stevenson_I"': ' (did you mean "stephenson-i"?), found "Stevenson_I" (string)',
    '"any six bar"': ' (did you mean "any six-bar"?), found "any six bar" (string)',
    '"wat-i"': ' (did you mean "watt-i"?), found "wat-i" (string)',
    '"four-bar"': ' (a four-bar is mechanism = "four-bar"; it is the baseline of every topology table), '
                  'found "four-bar" (string)',
    '"hexapod"': ', found "hexapod" (string)',
    "3": ", found 3",
    "true": ", found true (boolean)",
    '["watt-i"]': ', found an array of 1: ["watt-i"]',
    "{ name = \"watt-i\" }": ", found a table",
}


@pytest.mark.parametrize("written", BAD_TOPOLOGY)
def test_a_bad_topology_is_one_located_line_with_a_hint(written):
    value, lines = read(HEAD + f"topology = {written}\n")
    expected = ("f.toml:4: linkage.topology: expected one of: watt-i, watt-ii, stephenson-i, stephenson-ii, "
                "stephenson-iii, any six-bar" + BAD_TOPOLOGY[written])
    assert value is None and lines == [expected]


def test_a_huge_topology_is_one_bounded_line():
    value, lines = read(HEAD + f'topology = "{"watt-" * 20000}"\n')
    assert value is None and len(lines) == 1 and len(lines[0]) < 1000 and lines[0].startswith("f.toml:4: linkage.topology")


@pytest.mark.parametrize("tables, line, found", [
    ('[joints]\nA = { at = [0, 0], ground = true }\n', 6, "[joints] as well"),
    ('[links]\ncrank = ["A", "B"]\n[drive]\ncrank = {}\n', 6, "[links] and [drive] as well"),
    ('[drive]\ncrank = {}\n[joints]\nA = { at = [0, 0] }\n[links]\nx = ["A", "B"]\n', 6,
     "[joints] and [links] and [drive] as well"),
])
def test_a_drawing_with_a_topology_is_one_line_at_its_first_table(tables, line, found):
    text = HEAD + 'topology = "watt-i"\n\n' + tables
    value, lines = read(text)
    first = text.splitlines()[line - 1].strip("[]")
    expected = (f'f.toml:{line}: {first}: expected no drawing with [linkage] topology = "watt-i" (linkcli draws '
                "the starting designs of the topology itself; to start from a drawing of your own, give [joints], "
                f"[links] and [drive] without topology), found {found}")
    assert value is None and lines == [expected]


def test_reading_a_topology_and_listing_its_choices_imports_no_numpy():
    code = ("import sys\nfrom linkcli.mechanisms.drawn import catalogue, topology\n"
            "assert len(catalogue.choices('any six-bar', 'path')) == 14\n"
            "assert 'numpy' not in sys.modules, 'numpy imported'")
    subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, cwd=ROOT)
