"""Motion generation: a four-bar whose coupler carries a body through the poses
(docs/format.md, motion-generation). Strategy by pose count (free timing):

* 2 poses: given ground pivots, each moving pivot lies on a line (dyads.moving_pivot_line);
  given moving pivots, each ground pivot on a perpendicular bisector; the pair of points
  on the two lines (a grid of LINE_STEPS each, LINE_SPAN characteristic lengths either side)
  with the best transmission is taken. Neither given: ground pivots A0 (within
  ground_pivot), B0 = A0 + ground (cos, sin)(ground_angle) and a point on each line drawn
  from a Latin hypercube of SEARCH_POPULATION within the bounds.
* 3 poses: given ground pivots, the moving pivots by inversion (dyads.moving_pivots_for_ground);
  given moving pivots, the ground pivots (circumcentres); neither: A0, B0 drawn from a
  Latin hypercube within the bounds, each completed by inversion.
* 4 poses: the centre-point / circle-point curves (burmester.centre_point_curve, CURVE_SAMPLES
  directions), every ordered pair of their dyads a candidate.
* 5 poses: every ordered pair of the Burmester dyads (burmester.burmester_dyads: complete).
* more than 5 poses, or prescribed timing: least squares (least_squares.solve_least_squares)
  on sum |P_i - T_i|^2 + (w dangle_i)^2, within the bounds (given ground pivots fixed).

Every candidate is screened for defects and constraints (screen.py). The reported linkage is
the best one without any: exact synthesis ranks by the worst transmission deviation from
90 deg over the working span, ties within a relative 1e-9 going to the first in generation
order (noise.first_min); least squares by its objective. None defect-free: status
infeasible, the message says which defects the candidates have; the one with the fewest
defects is reported.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.io.bounds import MAX_LENGTH
from linkcli.noise import first_min
from linkcli.search.budget import Budget
from linkcli.search.sampling import latin_hypercube
from linkcli.solution import Solution, SolverRecord, Status

from . import assemble, burmester, dyads, least_squares, no_candidates, sections
from .box import design_box
from .poses import as_poses, characteristic_length
from .result import solution
from .schema import EXACT_POSES
from .screen import screen

PIVOT_SPAN = 4.0  # missing ground_pivot bound: the centroid +- this many characteristic lengths
LENGTH_SPAN = 6.0  # missing length bound: (LENGTH_FLOOR, this] characteristic lengths
LENGTH_FLOOR = 0.05
LINE_STEPS = 41  # two poses, given pivots: points tried on each line
LINE_SPAN = 3.0  # ... within this many characteristic lengths of the line's nearest point
SEARCH_POPULATION = 4000  # candidates drawn when no pivot is given (2 or 3 poses)
CURVE_SAMPLES = 181  # four poses: directions sampled on the centre-point curve
LISTED = 12  # searched families: the best this many candidates are listed
DEFAULT_BUDGET = 20_000_000  # least squares: objective evaluations


def solve(problem) -> Solution:
    """The design of the problem's mechanism, by its home's synthesis face
    (mechanisms.synthesis): the four-bar's below (`solve_four_bar`)."""
    from linkcli.mechanisms import synthesis
    return synthesis.solve("motion-generation", problem)


def solve_four_bar(problem) -> Solution:
    """The four-bar's motion design (the module docstring's strategy by pose count)."""
    poses = as_poses(problem.poses)
    n = len(poses)
    scale = characteristic_length(poses)
    with np.errstate(all="ignore"):
        if problem.timing == "prescribed" or n > EXACT_POSES:
            found, chosen = _least_squares(problem, poses, scale)
        else:
            method, family, g1, m1, g2, m2, notes, *dyads_found = _exact_candidates(problem, poses, scale)
            found, chosen = _choose_exact(problem, poses, scale, method, family, g1, m1, g2, m2, notes,
                                          dyads_found[0] if dyads_found else None)
    if problem.meta.front is not None and chosen is not None:  # a Pareto front from this design
        from .pareto import front  # (linkcli.pareto)
        return front(problem, poses, scale, chosen, found)
    return found


# ---------------------------------------------------------------- exact synthesis

def _exact_candidates(problem, poses, scale):
    """(method, family, G1, M1, G2, M2, notes): candidate dyad pairs (K, 2) each, in
    generation order; family "given" | "search" | "curve" | "burmester"."""
    n = len(poses)
    rng = np.random.default_rng(problem.meta.solver.seed)
    if n == 2:
        return _two_poses(problem, poses, scale, rng)
    if n == 3:
        return _three_poses(problem, poses, scale, rng)
    translation = no_candidates.translation_reason(poses, problem.meta.units)
    if n == 4:
        # the curve is drawn as a pencil of lines through the pole of the first two poses:
        # start from a pair that turns the body (a translation's pole is at infinity); the
        # centre points and the moving pivots (body frame) do not depend on the order
        pair = no_candidates.rotating_pair(poses)
        if pair is None:
            return "centre-point curve", "curve", *(np.zeros((0, 2)),) * 4, [translation]
        first = list(pair) + [k for k in range(n) if k not in pair]
        curve = burmester.centre_point_curve(poses[first], samples=CURVE_SAMPLES)
        g, m = curve.pairs()
        i, j = np.nonzero(~np.eye(len(g), dtype=bool))
        notes = [] if len(g) else [translation or no_candidates.curve_reason()]
        return "centre-point curve", "curve", g[i], m[i], g[j], m[j], notes
    res = burmester.burmester_dyads(poses)
    k = len(res.ground)
    i, j = np.nonzero(~np.eye(k, dtype=bool))
    notes = [] if k >= 2 else [translation or no_candidates.burmester_reason(k)]
    return ("burmester", "burmester", res.ground[i], res.moving[i], res.ground[j], res.moving[j], notes,
            res)


def _pivot_box(problem, poses, scale, rng, count):
    """A0 (count, 2), B0 (count, 2) drawn within ground_pivot, ground and ground_angle
    (defaults: PIVOT_SPAN, LENGTH_SPAN characteristic lengths, a full turn)."""
    cen = poses[:, :2].mean(0)
    gp = problem.ground_pivot or ((cen[0] - PIVOT_SPAN * scale, cen[0] + PIVOT_SPAN * scale),
                                  (cen[1] - PIVOT_SPAN * scale, cen[1] + PIVOT_SPAN * scale))
    d = problem.lengths.get("ground") or (LENGTH_FLOOR * scale, LENGTH_SPAN * scale)
    ga = problem.ground_angle or (-math.pi, math.pi)
    lo = np.array([gp[0][0], gp[1][0], max(d[0], LENGTH_FLOOR * scale * 1e-3), ga[0]])
    hi = np.array([gp[0][1], gp[1][1], d[1], ga[1]])
    lo[:3], hi[:3] = np.maximum(lo[:3], [-MAX_LENGTH, -MAX_LENGTH, 0.0]), np.minimum(hi[:3], MAX_LENGTH)  # sizes a file accepts
    unit = latin_hypercube(rng, count, 4)
    x = lo + unit * (hi - lo)
    a0 = x[:, :2]
    b0 = a0 + x[:, 2:3] * np.stack([np.cos(x[:, 3]), np.sin(x[:, 3])], -1)
    return a0, b0, unit


def _line_points(lines, offsets):
    """Points p + t e of each line for every offset t: (len(offsets), 2) per line."""
    return [ln.point + offsets[:, None] * ln.direction if ln.status == "ok" else None for ln in lines]


def _two_poses(problem, poses, scale, rng):
    t = np.linspace(-LINE_SPAN, LINE_SPAN, LINE_STEPS) * scale
    if problem.ground_pivots is not None or problem.moving_pivots is not None:
        given_ground = problem.ground_pivots is not None
        pivots = np.array(problem.ground_pivots if given_ground else problem.moving_pivots, float)
        make = dyads.moving_pivot_line if given_ground else dyads.ground_pivot_line
        lines = [make(poses, p) for p in pivots]
        pts = []
        for p, ln in zip(pivots, lines):
            if ln.status == "none":
                return "two poses", "given", *(np.zeros((0, 2)),) * 4, [
                    "no dyad: the poses differ by a translation along the pivot's normal"]
            if ln.status == "any":  # every point works: the grid about the body origin / centroid
                base = np.zeros(2) if given_ground else poses[:, :2].mean(0)
                pts.append(base + np.stack([t, np.zeros_like(t)], -1))
            else:
                near = np.zeros(2) if given_ground else poses[:, :2].mean(0)
                foot = ln.point + ((near - ln.point) @ ln.direction) * ln.direction
                pts.append(foot + t[:, None] * ln.direction)
        i, j = np.meshgrid(np.arange(LINE_STEPS), np.arange(LINE_STEPS), indexing="ij")
        i, j = i.ravel(), j.ravel()
        one, two = pts[0][i], pts[1][j]
        if given_ground:
            return "two poses, given ground pivots", "given", np.broadcast_to(pivots[0], one.shape), one, \
                np.broadcast_to(pivots[1], two.shape), two, []
        return "two poses, given moving pivots", "given", one, np.broadcast_to(pivots[0], one.shape), \
            two, np.broadcast_to(pivots[1], two.shape), []
    a0, b0, unit = _pivot_box(problem, poses, scale, rng, SEARCH_POPULATION)
    extra = latin_hypercube(rng, SEARCH_POPULATION, 2) * 2 - 1  # the point on each line
    coef = dyads.coefficients(poses[:2])
    out = []
    for g, s in ((a0, extra[:, 0]), (b0, extra[:, 1])):
        row = coef.moving_rows(g)[:, 0]  # normal . M + const = 0
        normal, const = row[:, :2], row[:, 2]
        nn = np.sum(normal * normal, -1)
        foot = -const[:, None] * normal / np.where(nn > 0, nn, np.nan)[:, None]
        direction = np.stack([-normal[:, 1], normal[:, 0]], -1) / np.sqrt(nn)[:, None]
        out.append(foot + (s * LINE_SPAN * scale)[:, None] * direction)
    return "two poses, search within bounds", "search", a0, out[0], b0, out[1], []


def _three_poses(problem, poses, scale, rng):
    if problem.ground_pivots is not None:
        g = np.array(problem.ground_pivots, float)
        m, singular = dyads.moving_pivots_for_ground(poses, g)
        notes = ([f"no moving pivot for ground pivot {k + 1} (at infinity or not unique: it lies on the "
                  "circle through the poles)" for k in np.flatnonzero(singular)])
        if singular.any():
            return "inversion", "given", *(np.zeros((0, 2)),) * 4, notes
        return "inversion", "given", g[:1], m[:1], g[1:], m[1:], []
    if problem.moving_pivots is not None:
        m = np.array(problem.moving_pivots, float)
        g, singular = dyads.ground_pivots_for_moving(poses, m)
        notes = ([f"no ground pivot for moving pivot {k + 1} (its three positions are collinear: a slider, "
                  "not a crank)" for k in np.flatnonzero(singular)])
        if singular.any():
            return "circumcentres", "given", *(np.zeros((0, 2)),) * 4, notes
        return "circumcentres", "given", g[:1], m[:1], g[1:], m[1:], []
    a0, b0, _ = _pivot_box(problem, poses, scale, rng, SEARCH_POPULATION)
    m1, s1 = dyads.moving_pivots_for_ground(poses, a0)
    m2, s2 = dyads.moving_pivots_for_ground(poses, b0)
    ok = ~s1 & ~s2
    notes = [] if ok.any() else [no_candidates.translation_reason(poses, problem.meta.units)
                                 or no_candidates.search_reason(len(ok))]
    return "inversion, search within bounds", "search", a0[ok], m1[ok], b0[ok], m2[ok], notes


def _choose_exact(problem, poses, scale, method, family, g1, m1, g2, m2, notes, burmester_dyads=None):
    """(Solution, chosen): the best defect-free candidate (module docstring) and its design
    (params, input angles, branch sign, angle weight; None without a candidate);
    `burmester_dyads`: five poses' BurmesterResult, reported as the `burmester` section (its
    real_dyads may be 0 or 1, when no candidate is left: the message says why). An exact
    family's search is complete: `converged` is true also when it proves that nothing fits."""
    u = problem.meta.units
    solver = SolverRecord(method, problem.meta.solver.seed, int(len(g1)), True)
    extra = {}
    if burmester_dyads is not None:
        extra["burmester"] = sections.burmester_section(burmester_dyads.ground, burmester_dyads.moving, u)
    if len(g1) == 0:
        return Solution(status=Status.INFEASIBLE, message="no candidate linkage: " + "; ".join(notes),
                        solver=solver, sections=extra), None
    params, phi, signs = assemble.dyad_pair_params(poses, g1, m1, g2, m2)
    res = screen(problem, poses, params, phi, signs, scale, exact=True)
    k = _best(res["count"], res["quality"])
    feasible = res["count"][k] == 0
    order = _listing_order(res, family)
    rows = sections.candidate_rows(res, params, g1, m1, g2, m2, order, u, family)
    extra = {"candidates": rows, **extra}
    if family in ("search", "curve"):
        extra["candidate_counts"] = sections.defect_counts(res)
    chosen = (params[k], phi[k], float(signs[k][0]), problem.angle_weight or scale)
    return solution(problem, poses, scale, params[k], phi[k], signs[k], res, k, feasible, solver, extra,
                     notes, objective=None), chosen


def _best(count, quality) -> int:
    """Fewest defects, then the best quality; ties to the first in generation order."""
    fewest = count.min()
    return int(first_min(np.where(count == fewest, quality, np.inf)))


def _listing_order(res, family):
    """Indices of the candidates listed: all of a given or Burmester family, the best
    LISTED of a searched one (defect-free first, then by quality, generation order on ties)."""
    total = len(res["count"])
    if family in ("given", "burmester"):
        return np.arange(total)
    key = np.lexsort((np.arange(total), res["quality"], res["count"]))
    return key[:LISTED]


# ---------------------------------------------------------------- many poses

def _least_squares(problem, poses, scale):
    """(Solution, chosen): the least-squares design and its params, input angles, branch
    sign and angle weight."""
    opts = problem.meta.solver
    counter = Budget(opts.budget or DEFAULT_BUDGET)
    lo, hi = design_box(problem, poses, scale)
    prescribed = problem.timing == "prescribed"
    offset = problem.input_offset or (0.0, 0.0)
    out = least_squares.solve_least_squares(
        poses, (lo, hi), branch=problem.branch, timing=problem.timing,
        input_angles=np.array(problem.input_angles) if prescribed else None, offset_bounds=offset,
        angle_weight=problem.angle_weight, grashof=None if problem.grashof == "any" else problem.grashof,
        transmission=problem.transmission, seed=opts.seed, budget=counter)
    phis = [out["input_angles"]]
    params = np.array([out["params"]])
    signs = np.full((1, len(poses)), -1.0 if out["branch"] == "open" else 1.0)
    res = screen(problem, poses, params, np.array(phis), signs, scale, exact=False)
    feasible = res["count"][0] == 0
    solver = SolverRecord("least-squares", opts.seed, int(out["evaluations"]), bool(out.get("converged", False)))
    extra = {"candidates": sections.polished_rows(out["candidates"], problem.meta.units)}
    notes = [] if out.get("confirmed", True) or not feasible else [
        f"no second round of starts reached the best design within {least_squares.MAX_ROUNDS} rounds: "
        "another seed or a larger budget may end lower"]
    chosen = (params[0], phis[0], float(signs[0][0]), float(out["angle_weight"]))
    return solution(problem, poses, scale, params[0], phis[0], signs[0], res, 0, feasible, solver, extra,
                     notes, objective=float(out["objective"]), weight=float(out["angle_weight"])), chosen
