"""Approximate motion generation: many poses (or bounds/constraints) by least squares.

Objective (docs/format.md, motion-generation): F = sum_i |P_i - T_i|^2 + (w * dangle_i)^2, P_i the
body origin reached at the input angle phi_i, T_i the target, dangle_i the wrapped angle
error in rad and w a length, by default the RMS distance of the target origins from their
centroid (poses.characteristic_length), so that a turn of 1 rad weighs like a typical
excursion of the body. Unknowns: the 10 linkage parameters (assemble.PARAM_NAMES) and,
with free timing, every phi_i; with prescribed timing phi_i = input_angles_i + offset.

Method: (1) a global stage evaluated on a whole population at once: a Latin hypercube
over the bounds, the linkages of the Burmester dyads of five-pose subsets (of four-pose
centre-point curves' best-fitting dyads once those run out: curve_dyads.py) and of 3-pose
inversions (moving pivots for sampled ground pivots), each scored with its best phi_i
from a grid (free timing: on every third grid angle, then about each pose's best for the
best rows; with many poses the rows are ranked on a few of them first); the body poses
from the loop closed as unit vectors (four_bar.closure); (2) the best distinct starts polished all at
once by the batched Levenberg-Marquardt (linkcli.search.levenberg_marquardt, bounds, a
step gaining less than 1e-15 of the cost ends a row) on the residual vector, without the
constraints first, then at stiffer penalties on the rows that break one, one row a design
(`one_design`: starts that ended in one basin share its penalty polish); with free timing
its normal equations are an arrow (each pose's angle moves that pose's residuals alone:
linkcli.search.arrow), solved in O(n); (3) the best polished design that has no branch or
order defect and meets the constraints is returned, (4) after a final Newton settle to
round-off (`_settle`, linkcli.search.kkt) on the constraints that bind, so that its
printed digits do not follow the polish's path. No scipy.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.search.arrow import Arrow
from linkcli.search.levenberg_marquardt import batch_lm
from linkcli.search.sampling import latin_hypercube

from . import assemble
from . import constraints as design_constraints
from .burmester import burmester_dyads_many
from .curve_dyads import fitting_dyads
from .dyads import moving_pivots_for_ground
from .poses import as_poses, characteristic_length

PENALTY = 10.0  # weight of the assembly violation (a length) in the residual vector
SCORE_ELEMENTS = 100_000  # (row, grid angle, pose) triples scored at once: each of the score's dozen
# elementwise passes then works on 0.8 MB arrays that stay in the cache (1_000_000: 8 MB arrays from memory;
# `_scored` of five tuning motion cases 1.70 -> 1.13-1.21 s, the same bits: the rows are independent)
REFINE = 3  # free timing: rows scored on every REFINE-th angle of the grid first (`_scored`)
REFINE_OFFSETS = np.array([-2, -1, 1, 2])  # ... then on these grid steps about each pose's best,
REFINE_ROWS = 512  # for this many rows, the best so scored (a round polishes the best few dozen's distinct ones)
SCREEN_POSES = 12  # free timing with more poses: the rows ranked on this many first,
SCREEN_ROWS = 256  # and the best this many scored on every pose
SETTLE_STEP = 1e-5  # unit box: the final polish's difference step (kkt.slopes); at 3e-5 the slopes'
# truncation error moved a flat valley's root 1.2e-7 (relative) above the polished point (case 19
# of benchmarks/constrained_variants.py), and the settle was refused; at 1e-5 and below it lands at 1e-11
CURVATURE_STEP = 1e-4  # unit box: differences of the constraints' slopes for their curvature (kkt)
SETTLE_GAIN = 1e-9  # relative: the polished design may be this much worse (round-off)
SETTLES = 4  # distinct designs settled (and so listed) at most, the best first
CONFIRM = 1e-7  # relative: another round's best this close confirms the best
MAX_ROUNDS = 6  # rounds of starts at most (the first CLAIM_ROUNDS side by side)
CLAIM_ROUNDS = 3  # rounds run at least before a confirmed best ends the search (not an exact fit):
# with two, the first two rounds ending in one wide basin claimed it (cases 11, 27, 83 of the
# constrained-variant study's tuning half, 8 of 75 runs)
EXACT_RMS = 1e-9  # rms error (relative to the characteristic length) of an exact fit
CURVE_DYADS = 6  # a four-pose curve's best-fitting dyads that make start linkages (every ordered pair)
SUBSETS = 12  # distinct random 5-pose subsets whose Burmester linkages join a round's population
# (near-exact fits of five poses: clipped into the bounds, starts near a bound-held optimum; 3
# found case 11's, two length bounds binding, in 2 of 5 seeds, 12 in 5 of 5), none that an earlier
# round took (`_subsets`)
DISTINCT = 0.1  # a round's picks are at least this far apart (Euclidean, each parameter over its
# bounds' width): the best-scored rows of a population crowd into one basin (tuning case 83: every
# start of three rounds at one local optimum 3.2 % above the best; 1e-3 before, 3 of 5 seeds `ok`
# there and 73 of 75 over the tuning motion cases; 0.1: 5 and 75)
SAME_DESIGN = 1e-6  # parameters this close (relative to the longest link) are one design
ITERATIONS = 400  # Levenberg-Marquardt steps of a polish, at most
PENALTY_ITERATIONS = 100  # ... of a penalty pass: it has to find the constraints that bind and
# come near the optimum along them, the final KKT polish holding them exactly (30 left case 35 of the
# constrained-variant study, a transmission window, 0.4 of the unit box from it: the settle's Newton
# steps did not converge, 5 seeds of 5 `not-converged`; 100: 5 `ok`; 400: 5 `ok`, 50 % slower; 50, now that a
# failed settle walks to the optimum first (`_walk`), kept every verdict of the study's 150 motion runs, but
# its settles, from farther, took twice the time: problems/bench/motion_many_window.toml 22 -> 49 ms a settle)
GAIN = 1e-15  # a polish has converged when a step gains less than this share of the cost
CONSTRAINT_WEIGHTS = (1e1, 1e3)  # penalty weights of a Grashof or window violation in the
# residual vector, each stiffer pass only while the polish leaves one (then the settle holds
# the binding ones exactly; a third pass at 1e5 changed no verdict of the study's motion cases)


def default_bounds(poses):
    """(lo, hi) in PARAM_NAMES order from the poses: pivots within 4 L of the centroid,
    lengths in [0.05 L, 6 L], angles free (L = characteristic_length)."""
    poses = as_poses(poses)
    cen, L = poses[:, :2].mean(0), characteristic_length(poses)
    lo = np.array([cen[0] - 4 * L, cen[1] - 4 * L, -np.pi, .05 * L, .05 * L, .05 * L, .05 * L,
                   -4 * L, -4 * L, -np.pi])
    hi = np.array([cen[0] + 4 * L, cen[1] + 4 * L, np.pi, 6 * L, 6 * L, 6 * L, 6 * L,
                   4 * L, 4 * L, np.pi])
    return lo, hi


def box_sample(rng, count, lo, hi):
    """count points of the box [lo, hi] from the house Latin hypercube (search.sampling)."""
    return lo + latin_hypercube(rng, count, len(lo)) * (hi - lo)


def _scores(params, poses, signs, phi_grid, weight, input_angles, counter=None):
    """Objective of each population row with its best phi per pose from phi_grid (free
    timing) or its prescribed angles; returns (objective (N,), phi (N, n)). With more than
    SCREEN_POSES poses (free timing) the rows are ranked on SCREEN_POSES of them, evenly
    spread, and the best SCREEN_ROWS scored on all (the others inf): the work grows like
    the poses, not like rows x poses. Rows are
    scored SCORE_ELEMENTS (row, grid angle, pose) triples at a time: bounded memory
    whatever the number of poses. An input angle where the row does not assemble scores
    inf; the angle error is |wrapped difference| = min(|d|, 2 pi - |d|) for d the
    difference of two angles in (-pi, pi]. `counter` (a search.budget.Budget, or None)
    is charged one evaluation a row at an input angle scored against every pose (`_scored`)."""
    n = len(poses)
    free = input_angles is None
    if free and n > SCREEN_POSES:  # ranked on a few poses first, the best rows on all of them
        few = np.unique(np.linspace(0, n - 1, SCREEN_POSES).round().astype(int))
        rough, _ = _scored(params, poses[few], signs, phi_grid, weight, None, counter)
        keep = np.argsort(rough, kind="stable")[:SCREEN_ROWS]
        keep = np.sort(keep[np.isfinite(rough[keep])])
        obj, best_phi = np.full(len(params), np.inf), np.zeros((len(params), n))
        obj[keep], best_phi[keep] = _scored(params[keep], poses, signs, phi_grid, weight, None, counter)
        return obj, best_phi
    return _scored(params, poses, signs, phi_grid, weight, input_angles, counter)


def _scored(params, poses, signs, phi_grid, weight, input_angles, counter=None):
    """`_scores` of every row on every pose. Free timing: each row's body poses on every
    REFINE-th grid angle against every pose; then, for the REFINE_ROWS rows best so scored,
    each pose's best refined on the grid angles between it and its two coarse neighbours
    (a row's best grid angle unless its cost curve has another, lower dip within 2 REFINE
    grid steps of no coarse angle); the other rows keep their coarse scores (a start is
    taken among the best few dozen). Charged to `counter`: a row at its prescribed angles one
    evaluation, a row at a coarse angle one, a refined row one an offset."""
    n = len(poses)
    charge = counter.add if counter is not None else (lambda count: None)
    target_angle = kin.wrap(poses[:, 2])
    if input_angles is not None:  # pose i at its own angle: (N, n)
        obj = np.empty(len(params))
        for rows in _chunks(len(params), n):
            obj[rows] = np.sum(_pose_costs(params[rows], input_angles, signs, poses, target_angle, weight), -1)
        charge(len(params))
        return np.where(np.isfinite(obj), obj, np.inf), np.broadcast_to(input_angles, (len(params), n)).copy()
    coarse = np.arange(0, len(phi_grid), REFINE)
    k = np.empty((len(params), n), int)
    cost = np.empty((len(params), n))
    for rows in _chunks(len(params), len(coarse) * n):
        every = _pose_costs(params[rows], phi_grid[coarse], signs, poses, target_angle, weight, every=True)
        k[rows] = np.argmin(every, 1)  # (N, n): each pose's best coarse angle
        cost[rows] = np.take_along_axis(every, k[rows][:, None, :], 1)[:, 0]
    chosen = coarse[k]
    obj = np.sum(cost, -1)
    best = np.sort(np.argsort(obj, kind="stable")[:REFINE_ROWS])
    charge(len(params) * len(coarse) + len(best) * len(REFINE_OFFSETS))
    for part in _chunks(len(best), len(REFINE_OFFSETS) * n):
        rows = best[part]
        at = chosen[rows][..., None] + REFINE_OFFSETS  # (N, n, r): the grid angles about each best
        at %= len(phi_grid)
        fine = _pose_costs(params[rows], phi_grid[at].reshape(len(rows), -1), signs, poses, target_angle, weight,
                           own=len(REFINE_OFFSETS))  # (N, n, r)
        both = np.concatenate([cost[rows][..., None], fine], -1)
        j = np.argmin(both, -1)  # (N, n): 0 the coarse angle, else an offset's
        obj[rows] = np.sum(np.take_along_axis(both, j[..., None], -1)[..., 0], -1)
        chosen[rows] = np.where(j == 0, chosen[rows], np.take_along_axis(at, np.maximum(j - 1, 0)[..., None], -1)[..., 0])
    return np.where(np.isfinite(obj), obj, np.inf), phi_grid[chosen]


def _chunks(count: int, per_row: int):
    """Slices of `count` rows, SCORE_ELEMENTS (row, angle, pose) triples at a time."""
    size = max(1, SCORE_ELEMENTS // max(1, per_row))
    return [slice(start, min(start + size, count)) for start in range(0, count, size)]


def _pose_costs(p, phis, signs, poses, target_angle, weight, every: bool = False, own: int = 0):
    """Squared pose errors |P - T|^2 + (w dangle)^2 of rows p at input angles phis (inf
    where the row does not assemble): pose i at the i-th angle ((N, n)), every angle against
    every pose (`every`: (N, K, n)), or the i-th `own` angles against pose i (`own`:
    phis (N, n own) -> (N, n, own)). dangle = min(|d|, 2 pi - |d|), d the difference of two
    angles in [-pi, pi]."""
    x, y, ex, ey, fr = assemble.body_frames(p, phis, signs)  # (N, K)
    x = np.where(fr.valid, x, np.inf)  # no assembly there: no score
    ang = np.arctan2(ey, ex)
    tx, ty, ta = poses[:, 0], poses[:, 1], target_angle
    if every:
        x, y, ang = x[:, :, None], y[:, :, None], ang[:, :, None]
    elif own:
        x, y, ang = (v.reshape(len(p), -1, own) for v in (x, y, ang))
        tx, ty, ta = tx[:, None], ty[:, None], ta[:, None]
    cost = x - tx
    cost *= cost
    dy = y - ty
    dy *= dy
    cost += dy
    d = np.abs(ang - ta)
    np.minimum(d, kin.TWO_PI - d, out=d)
    d *= weight
    d *= d
    cost += d
    return cost


def residuals(x_full, poses, sign, weight, timing_angles):
    """Residual vectors [dx_i, dy_i, w dangle_i, PENALTY * violation_i] of designs
    x_full (..., 10 + n) (free timing: the n input angles) or (..., 11) (prescribed: one
    offset added to timing_angles); vectorized over the leading axes. The angle error is
    the direction of the body's axis e seen from the target's t, atan2(t x e, t . e), wrapped
    in [-pi, pi] (`assemble.body_frames`); the violation is rho's distance outside
    [|b - c|, b + c]."""
    x_full = np.asarray(x_full, float)
    p = x_full[..., :10]
    phi = x_full[..., 10:] if timing_angles is None else timing_angles + x_full[..., 10:11]
    x, y, ex, ey, fr = assemble.body_frames(p, phi, sign)
    b, c = p[..., 5, None], p[..., 6, None]
    viol = np.maximum(0.0, np.maximum(fr.rho - (b + c), np.abs(b - c) - fr.rho))
    tx, ty = np.cos(poses[:, 2]), np.sin(poses[:, 2])
    dang = np.arctan2(tx * ey - ty * ex, tx * ex + ty * ey)
    return np.concatenate([np.stack([x - poses[:, 0], y - poses[:, 1]], -1).reshape(x.shape[:-1] + (-1,)),
                           weight * dang, PENALTY * viol], -1)


def _starts(poses, lo, hi, rng, population, signs, spread: bool = True, taken: set | None = None):
    """Population rows: LHS, Burmester linkages of 5-pose subsets (`spread`: the evenly
    spread one among them; random ones always, none of the subsets in `taken`, the earlier
    rounds', to which this population's are added), 3-pose inversions."""
    n = len(poses)
    rows = [box_sample(rng, population, lo, hi)]
    if n >= 5:
        taken = set() if taken is None else taken
        spread_one = [np.linspace(0, n - 1, 5).round().astype(int)] if spread else []
        subsets = [sub for sub in spread_one if tuple(sub.tolist()) not in taken]
        drawn = _subsets(rng, n, SUBSETS, frozenset(taken))
        subsets += drawn
        taken.update(tuple(sub.tolist()) for sub in subsets)
        dyads = [(res.ground, res.moving)
                 for res in burmester_dyads_many(np.array([poses[sub] for sub in subsets]).reshape(-1, 5, 3))]
        if len(drawn) < SUBSETS:  # the five-pose subsets run out: four-pose curves' best dyads instead
            fours = _subsets(rng, n, SUBSETS - len(drawn), frozenset(taken), size=4)
            taken.update(tuple(sub.tolist()) for sub in fours)
            dyads += [fitting_dyads(poses, sub, CURVE_DYADS) for sub in fours]
        for ground, moving in dyads:
            k = len(ground)
            if k >= 2:
                i, j = np.nonzero(~np.eye(k, dtype=bool))
                p, _, _ = assemble.dyad_pair_params(poses, ground[i], moving[i], ground[j], moving[j])
                rows.append(p)
    if n >= 3:
        sub = np.array([0, n // 2, n - 1])
        pivots = box_sample(rng, population, lo, hi)
        g1 = pivots[:, :2]
        g2 = g1 + pivots[:, 3:4] * np.stack([np.cos(pivots[:, 2]), np.sin(pivots[:, 2])], -1)
        m1, s1 = moving_pivots_for_ground(poses[sub], g1)
        m2, s2 = moving_pivots_for_ground(poses[sub], g2)
        ok = ~s1 & ~s2
        p, _, _ = assemble.dyad_pair_params(poses, g1[ok], m1[ok], g2[ok], m2[ok])
        rows.append(p)
    allp = np.concatenate(rows)
    allp = allp[np.all(np.isfinite(allp), -1)]
    for j in (2, 9):  # the angles into their windows (the nearest edge, round the circle, when outside)
        allp[:, j] = into_window(allp[:, j], lo[j], hi[j])
    return np.clip(allp, lo, hi)  # the other rows outside the bounds: clipped into them


def into_window(angle, lo: float, hi: float):
    """Angles (rad) as the same directions within [lo, hi] (hi - lo <= 2 pi), or, for one
    outside the window, the edge nearer round the circle: a window such as [-230, -203] deg
    holds directions that wrapping into (-pi, pi] would put outside it."""
    d = np.mod(np.asarray(angle, float) - lo, kin.TWO_PI)  # [0, 2 pi) past lo
    width = hi - lo
    past = d - width  # > 0: beyond hi by this much, and short of lo (a turn on) by 2 pi - d
    return np.where(past <= 0.0, lo + d, np.where(past <= kin.TWO_PI - d, hi, lo))


def _subsets(rng, n: int, count: int, taken: frozenset = frozenset(), size: int = 5) -> list[np.ndarray]:
    """`count` distinct `size`-pose subsets of n poses drawn at random, none of `taken` (which
    may hold subsets of other sizes too; every one left, in a random order, when no more
    than 4 `count` are left; none when all are taken), each sorted. A subset's Burmester linkages are the same whichever round
    computes them: two rounds that polish one such start end at one point without being
    two independent arrivals (the motion study's tuning and reporting halves: 10 of 150
    runs claimed their best on rounds that had all polished one bit-identical start), so
    a round takes only subsets no earlier round took."""
    left = math.comb(n, size) - sum(1 for sub in taken if len(sub) == size)
    if left <= 4 * count:  # few: every subset left, shuffled, the first `count`
        every = np.array([sub for sub in itertools.combinations(range(n), size) if sub not in taken], int)
        return list(every[rng.permutation(len(every))[:count]]) if len(every) else []
    seen, out = set(taken), []
    while len(out) < count:  # many: draws, a repeat or a taken one drawn again (rare: > 4 count left)
        sub = tuple(np.sort(rng.choice(n, size, replace=False)).tolist())
        if sub not in seen:
            seen.add(sub)
            out.append(np.array(sub))
    return out


def solve_least_squares(poses, bounds=None, *, branch="either", timing="free",
                        input_angles=None, offset_bounds=(0.0, 0.0), angle_weight=None,
                        grashof=None, transmission=None, seed=0, population=2000,
                        polish=16, grid=180, budget=None) -> dict:
    """Best four-bar through `poses` (n, 3; angles rad) in the least-squares sense.

    bounds: (lo, hi) arrays (10,) in PARAM_NAMES order (lo == hi fixes a value), default
    default_bounds; branch "open" | "crossed" | "either"; timing "free" or "prescribed"
    with input_angles (n,) rad and offset_bounds (lo, hi) rad; grashof: a class name the
    design must have, or None; transmission (lo, hi) rad at every pose, or None.
    Returns dict: params (10,), branch, input_angles (n,), objective, achieved (n, 3),
    position_error (n,), angle_error (n,), checks (assemble.check_linkage), feasible,
    why (reason when not feasible), angle_weight, evaluations (objective evaluations),
    converged (the polish of the best met its tolerances and two rounds found it),
    confirmed (two rounds of starts found it, CLAIM_ROUNDS run), candidates (every polished design
    settled: params, branch, objective, defects). budget: a search.budget.Budget that
    counts the evaluations (a fresh one without a cap when None); the polishes stop at its cap.

    Rounds (`Search.round`): each draws its own population (population / 2 rows of each
    kind) and polishes its best polish / 2 distinct starts per branch; the first CLAIM_ROUNDS
    run side by side (one batched polish: at these sizes a step is mostly numpy's call overhead,
    and a round's pool does not depend on another's results, so they are the rounds run in
    turn, with the same draws). The best is confirmed when another round's best
    ends within CONFIRM of it (a second arrival from other starts; two starts of one
    population can share a basin) and CLAIM_ROUNDS rounds have run, or is an exact fit;
    otherwise rounds follow, at most MAX_ROUNDS, while the budget lasts. An unconfirmed
    best is not `converged`."""
    from linkcli.search.budget import Budget

    counter = budget if budget is not None else Budget(2**62)
    search = Search(as_poses(poses), bounds, branch, timing, input_angles, offset_bounds, angle_weight,
                    grashof, transmission, grid, counter)
    rng = np.random.default_rng(seed)
    size, picks = max(1, population // 2), max(1, polish // 2)
    rounds = search.rounds([search.pool(rng, size, picks, spread=(i == 0)) for i in range(CLAIM_ROUNDS)])
    best, confirmed = search.best_of(rounds)
    while (not confirmed or (len(rounds) < CLAIM_ROUNDS and not search.fits_exactly(best))) \
            and len(rounds) < MAX_ROUNDS and counter.left > 0:
        rounds += search.rounds([search.pool(rng, size, picks, False)])
        best, confirmed = search.best_of(rounds)
    return search.outcome(rounds, best, confirmed)


class Search:
    """The many-pose least-squares search of one problem: its scoring, rounds of polished
    starts and their settle (`solve_least_squares`)."""

    def __init__(self, poses, bounds, branch, timing, input_angles, offset_bounds, angle_weight, grashof,
                 transmission, grid, counter):
        n = len(poses)
        self.poses, self.counter, self.grashof, self.transmission = poses, counter, grashof, transmission
        lo, hi = (np.asarray(v, float) for v in (bounds if bounds is not None else default_bounds(poses)))
        self.lo, self.hi = lo, hi
        self.weight = characteristic_length(poses) if angle_weight is None else float(angle_weight)
        self.scale = characteristic_length(poses)
        self.prescribed = timing == "prescribed"
        self.t_angles = np.asarray(input_angles, float) if self.prescribed else None
        self.offset_bounds = offset_bounds
        self.signs = {"open": [-1.0], "crossed": [1.0], "either": [-1.0, 1.0]}[branch]
        self.phi_grid = np.linspace(-np.pi, np.pi, grid, endpoint=False)
        grashof_held = grashof if grashof not in (None, "any") else None
        self.m_cons = design_constraints.count(grashof_held, transmission, n)
        t_angles = self.t_angles

        def constraint_values(x):  # (..., m) g <= 0 feasible, length unit
            phi = x[..., 10:] if t_angles is None else t_angles + x[..., 10:11]
            return design_constraints.values(x, phi, grashof_held, transmission, self.scale)

        self.constraint_values = constraint_values
        if self.prescribed:
            tlo, thi = np.array([offset_bounds[0]]), np.array([offset_bounds[1]])
        else:
            tlo, thi = np.full(n, -4 * np.pi), np.full(n, 4 * np.pi)
        self.lo_full, self.hi_full = np.concatenate([lo, tlo]), np.concatenate([hi, thi])
        self.mask = np.concatenate([hi > lo, thi > tlo])
        # angles free over a full turn (ground, coupler, a prescribed offset): a polish may cross
        # the seam of their range (one more turn each side), `wrapped` brings them back into it
        self.periodic = [j for j in ((2, 9, 10) if self.prescribed else (2, 9))
                         if self.hi_full[j] - self.lo_full[j] >= kin.TWO_PI * (1.0 - 1e-12)]
        self.turn_lo = self.lo_full[self.periodic].copy()
        self.lo_full[self.periodic] -= kin.TWO_PI
        self.hi_full[self.periodic] += kin.TWO_PI
        self.fit = PoseFit(poses, self.weight, t_angles, self.mask, self.lo_full, self.hi_full, counter,
                           constraint_values, self.m_cons,
                           transmission is not None and grashof_held not in design_constraints.FULL_TURN)
        self.exact = n * (EXACT_RMS * self.scale) ** 2  # an objective this small fits exactly
        self.settled_as = []  # (params before, settled result or None: it failed): designs settled so far
        self.taken = set()  # 5-pose subsets whose Burmester linkages earlier rounds' populations hold
        self.tries = 0

    def pool(self, rng, population, polish, spread):
        """A round's starts: (sign, x0) of the best `polish` distinct rows per branch of a
        fresh population, scored."""
        starts = _starts(self.poses, self.lo, self.hi, rng, population, self.signs, spread, self.taken)
        pool = []
        for sign in self.signs:
            if self.prescribed:
                ob = self.offset_bounds
                offs = np.linspace(ob[0], ob[1], 9 if ob[1] > ob[0] else 1)
                best = None
                for off in offs:
                    sc, ph = _scores(starts, self.poses, sign, None, self.weight, self.t_angles + off, self.counter)
                    best = (sc, np.full(len(sc), off)) if best is None else (
                        np.where(sc < best[0], sc, best[0]), np.where(sc < best[0], off, best[1]))
                score, extra = best[0], best[1][:, None]
            else:
                score, extra = _scores(starts, self.poses, sign, self.phi_grid, self.weight, None, self.counter)
            order = np.argsort(score, kind="stable")[:polish * 4]
            chosen = []
            width = self.hi - self.lo + 1e-300
            for k in order:  # pick distinct starts (a short loop over the best few)
                if np.isfinite(score[k]) and all(np.linalg.norm((starts[k] - starts[c]) / width) > DISTINCT
                                                 for c in chosen):
                    chosen.append(k)
                if len(chosen) == polish:
                    break
            pool += [(sign, np.concatenate([starts[k], extra[k]])) for k in chosen]
        return pool

    def rounds(self, pools):
        """Polish the pools' starts together (one batched polish), settle the designs they
        reach; the results (dicts of `_evaluate`) of each pool."""
        rows = [row for pool in pools for row in pool]
        if not rows:
            return [[] for _ in pools]
        signs = np.array([sign for sign, _ in rows])
        x0 = np.clip(np.array([x for _, x in rows]), self.lo_full, self.hi_full)
        x, converged, penalized = self.fit.polish(x0, signs)
        x = self.wrapped(x)
        results = []
        for i, sign in enumerate(signs):
            results.append(_evaluate(x[i], self.poses, sign, self.weight, self.t_angles, self.grashof,
                                     self.transmission))
            results[-1].update(converged=bool(converged[i]), penalized=bool(penalized[i]), x=x[i], sign=sign)
        bounds = np.cumsum([0] + [len(pool) for pool in pools])
        for a, b in zip(bounds[:-1], bounds[1:]):
            results[a:b] = self._settle_all(results[a:b])
        return [results[a:b] for a, b in zip(bounds[:-1], bounds[1:])]

    def _settle_all(self, results):
        """One round's results, settled: its best; with constraints the best SETTLES
        distinct designs over all rounds, and each round's best beyond them (a penalty
        polish ends at a point whose last digits follow round-off, and they are listed; a
        round confirms another's best only settled, `best_of`). With constraints the rows
        are taken by objective, the penalized ones among the feasible: a penalty polish ends
        just outside a binding constraint, which the settle holds. A start that reached a
        design settled already takes its settled result (they are one design, listed once),
        not a settle again; one whose settle failed is not tried again (the same start
        fails the same way, and would spend the SETTLES tries the others need). Without
        constraints only the round's best is settled, and every other row of its design takes
        the settled result too: left polished, one ending a few 1e-17 below the settled value
        would be the round's best, unsettled (the motion study's tuning case 123, seed 4)."""
        results = list(results)
        key = (lambda r: (not (r["feasible"] or r["penalized"]), r["objective"])) if self.m_cons else _key
        order = sorted(range(len(results)), key=lambda i: key(results[i]))
        first = True  # the round's best is settled whatever the count
        for i in order:
            if not (results[i]["feasible"] or self.m_cons):
                continue
            p = results[i]["params"]
            same = [out for q, out in self.settled_as
                    if np.max(np.abs(p - q)) <= SAME_DESIGN * float(max(p[3:7]))]
            if same:
                if same[0] is not None:
                    results[i], first = dict(same[0]), False
                continue  # one that failed to settle fails again: no try spent on it
            if not first and (not self.m_cons or self.tries >= SETTLES):
                continue  # the worse designs stay unsettled, and unlisted
            self.tries, first = self.tries + 1, False
            settled = _settle(self.counter, *self._setup(results[i]))
            if settled is not None:
                settled = self.wrapped(settled)
                out = _evaluate(settled, self.poses, results[i]["sign"], self.weight, self.t_angles,
                                self.grashof, self.transmission)
                if out["feasible"] and (not results[i]["feasible"] or
                                        out["objective"] <= results[i]["objective"] * (1.0 + SETTLE_GAIN)):
                    out.update(converged=True, settled=True, sign=results[i]["sign"], penalized=True)
                    results[i] = out
                    self.settled_as.append((p, out))
                    continue
            self.settled_as.append((p, None))
        return results

    def _setup(self, result):
        """What `_settle` needs of a polished design: residuals and constraints of its
        free variables, the full vector, the mask, the bounds, its sign and the scale."""
        x0, sign, mask = result["x"], result["sign"], self.mask
        poses, weight, t_angles, values = self.poses, self.weight, self.t_angles, self.constraint_values

        def design(z):
            z = np.asarray(z, float)
            out = np.broadcast_to(x0, z.shape[:-1] + x0.shape).copy()
            out[..., mask] = z
            return out

        def fun(z):
            return residuals(design(z), poses, sign, weight, t_angles)

        def cons(z):
            return values(design(z))

        return (fun, cons if self.m_cons else None, x0, mask, self.lo_full, self.hi_full, sign, self.scale,
                t_angles is None)

    def wrapped(self, x):
        """Designs x (..., 10 + t) with each full-turn angle brought into [lo, lo + 2 pi) of its
        range (the same linkage: the angles enter through their cosine and sine alone)."""
        x = np.array(x, float)
        x[..., self.periodic] = self.turn_lo + np.mod(x[..., self.periodic] - self.turn_lo, kin.TWO_PI)
        return x

    def fits_exactly(self, result) -> bool:
        """A feasible result whose objective is within round-off of 0 (`exact`): nothing to confirm."""
        return result is not None and result["feasible"] and result["objective"] <= self.exact

    def best_of(self, rounds):
        """(the best result over the rounds, whether another round's best ends within
        CONFIRM of it, or it fits exactly)."""
        bests = [min(r, key=_key) for r in rounds if r]
        if not bests:
            return None, False
        best = min(bests, key=_key)
        if not best["feasible"]:
            return best, False
        if self.fits_exactly(best):
            return best, True
        near = [b for b in bests if b["feasible"]
                and b["objective"] - best["objective"] <= CONFIRM * best["objective"]]
        return best, len(near) >= 2

    def outcome(self, rounds, best, confirmed) -> dict:
        results = [r for rs in rounds for r in rs]
        order = sorted(range(len(results)), key=lambda i: _key(results[i]))
        if self.m_cons:  # listed: the best, and the others the final polish settled (an end point it
            # did not settle has last digits that follow the search's path, along a penalty or a
            # flat valley); a design reached from several starts is one entry (polished_rows)
            order = order[:1] + [i for i in order[1:] if results[i].get("settled")]
        ranked = [results[i] for i in order]
        out = dict(ranked[0])
        out["confirmed"] = bool(confirmed)
        # an exact fit has nothing left to converge to (as in path generation): its polish may
        # stop at 1e-27 on a step that gains nothing measurable, without meeting the gain test
        out["converged"] = (bool(out.get("converged")) and bool(confirmed)) or self.fits_exactly(out)
        out["angle_weight"] = self.weight
        out["evaluations"] = self.counter.used
        out["candidates"] = [{k: r[k] for k in ("params", "branch", "objective", "feasible", "why")}
                             for r in ranked]
        return out


def _key(result):
    """Feasible first, then the lower objective."""
    return (not result["feasible"], result["objective"])


class PoseFit:
    """The polish of many designs at once (`linkcli.search.levenberg_marquardt.batch_lm`):
    full vectors x (N, 10 + t) of which the `mask` variables move within [lo, hi], each row
    with its branch sign; residuals `residuals` (plus `penalty` times the constraints'
    violations, when set); evaluations counted against `budget`. With free timing the
    Jacobian is an arrow (linkcli.search.arrow): pose i's input angle moves pose i's
    residuals alone, so its columns come from two shifted points for all the angles at
    once (central differences, like the linkage's columns: step eps^(1/3) max(1, |z|)),
    and the Levenberg-Marquardt normal equations are solved in O(n)."""

    def __init__(self, poses, weight, t_angles, mask, lo, hi, budget, constraint_values, m_cons,
                 window_at_poses: bool):
        self.poses, self.weight, self.t_angles, self.mask = poses, weight, t_angles, mask
        self.lo, self.hi, self.budget = lo[mask], hi[mask], budget
        self.constraint_values, self.m_cons = constraint_values, m_cons
        self.window_at_poses = window_at_poses  # the window's 2n rows, one per pose and edge, last
        self.scale = characteristic_length(poses)
        self.n_link = int(np.sum(mask[:10]))
        self.penalty = None
        self.x0 = self.sign = None

    def full(self, z, rows):
        """Full vectors of rows z of the batch (their fixed entries from x0)."""
        x = self.x0[rows].copy()
        x[:, self.mask] = z
        return x

    def residuals(self, z, rows, sign=None) -> np.ndarray:
        """Counted residuals of rows z (`sign`: their branch signs, when not the rows')."""
        self.budget.add(len(z))
        x = self.full(z, rows)
        sign = self.sign[rows] if sign is None else sign
        r = residuals(x, self.poses, sign[:, None], self.weight, self.t_angles)
        if self.penalty is None:
            return r
        return np.concatenate([r, self.penalty * np.maximum(0.0, self.constraint_values(x))], axis=1)

    def owners(self) -> np.ndarray:
        """Each residual's pose (whose input angle moves it), -1 for the rows no angle moves
        (the Grashof class, a window over the full turn)."""
        n = len(self.poses)
        each = np.arange(n)
        own = [np.repeat(each, 2), each, each]  # position (x, y), angle, assembly
        if self.penalty is not None and self.m_cons:
            at_poses = 2 * n if self.window_at_poses else 0
            own += [np.full(self.m_cons - at_poses, -1)] + ([each, each] if at_poses else [])
        return np.concatenate(own)

    def jacobian(self, z, rows, r0):
        """Central differences: every column apart (prescribed timing), or the linkage's
        apart and the input angles' together (free timing: an `Arrow`)."""
        rows = np.arange(len(self.sign))[rows]
        n_rows, k = z.shape
        h = np.finfo(float).eps ** (1 / 3) * np.maximum(1.0, np.abs(z))
        arrow = self.t_angles is None
        cols = self.n_link if arrow else k
        shifts = np.zeros((cols + (1 if arrow else 0), k))
        shifts[np.arange(cols), np.arange(cols)] = 1.0
        if arrow:
            shifts[cols, cols:] = 1.0
        step = shifts[None, :, :] * h[:, None, :]  # (N, s, k)
        zz = np.concatenate([z[:, None, :] + step, z[:, None, :] - step], axis=1).reshape(-1, k)
        reps = 2 * len(shifts)
        rr = self.residuals(zz, np.repeat(rows, reps), sign=np.repeat(self.sign[rows], reps))
        rr = rr.reshape(n_rows, reps, -1)
        plus, minus = rr[:, :len(shifts)], rr[:, len(shifts):]
        dense = np.transpose((plus[:, :cols] - minus[:, :cols]) / (2.0 * h[:, :cols, None]), (0, 2, 1))
        if not arrow:
            return dense
        owner = self.owners()
        ht = h[:, cols:]  # each pose's step
        at = np.where(owner >= 0, owner, 0)
        local = np.where(owner >= 0, (plus[:, cols] - minus[:, cols]) / (2.0 * ht[:, at]), 0.0)
        return Arrow(dense, local, owner, len(self.poses))

    def polish(self, x0, sign):
        """Levenberg-Marquardt on every row at once: without the constraints first, then,
        on the rows that break one, at the penalty weights CONSTRAINT_WEIGHTS in turn.
        Returns (x, converged, penalized), each (N, ...)."""
        x, converged = x0.copy(), np.zeros(len(x0), dtype=bool)
        penalized = np.zeros(len(x0), dtype=bool)
        todo = np.arange(len(x0))
        owner = todo
        span = self.hi - self.lo
        for penalty in [None] + (list(CONSTRAINT_WEIGHTS) if self.m_cons else []):
            if penalty is not None:
                if penalty == CONSTRAINT_WEIGHTS[0]:  # one penalty polish a design
                    owner = one_design(x, sign, self.scale)
                    todo = todo[owner[todo] == todo]
                todo = todo[np.any(self.constraint_values(x[todo]) > 0.0, axis=1)]
                penalized[todo] = True
            if not len(todo):
                break
            self.penalty = penalty
            self.x0, self.sign = x[todo], sign[todo]
            z0 = np.clip(x[todo][:, self.mask], self.lo + 1e-12 * span, self.hi - 1e-12 * span)
            z, _, conv = batch_lm(self, z0, ITERATIONS if penalty is None else PENALTY_ITERATIONS, gain=GAIN)
            x[np.ix_(todo, np.flatnonzero(self.mask))] = z
            converged[todo] = conv
        self.penalty = None
        return x[owner], converged[owner], penalized[owner]


def one_design(x, sign, scale: float) -> np.ndarray:
    """Each row's representative among designs x (N, 10 + t) polished without the
    constraints: the first row of its sign whose lengths and pivots lie within SAME_DESIGN
    scale and whose angles (ground, coupler, input or offset) lie within SAME_DESIGN rad,
    round the circle, of its own (a row's representative is a representative: a chain
    ends at its first row). Starts that ended in one basin are one design: its penalty
    passes from there are run once (the motion study's windows: 48 rows of three rounds
    end at 6 or 7 designs)."""
    angle = np.zeros(x.shape[1], dtype=bool)
    angle[[2, 9]] = True
    angle[10:] = True
    diff = x[:, None, :] - x[None, :, :]
    diff[..., angle] = kin.wrap(diff[..., angle])
    diff[..., ~angle] /= scale
    near = (np.max(np.abs(diff), axis=-1) <= SAME_DESIGN) & (sign[:, None] == sign[None, :])
    owner = np.argmax(near, axis=1)  # the first row near each (itself at the latest)
    while np.any(owner[owner] != owner):
        owner = owner[owner]
    return owner


def _settle(counter, fun, cons, x, mask, lo, hi, sign, scale, free_timing: bool):
    """The best polished design after the final polish (linkcli.search.kkt): Gauss-Newton
    on its residuals in the unit box of its free variables, the bounds and the constraints
    (`cons`, g <= 0, or None) that bind held, to round-off, so that the printed digits are
    the optimum's and not those of least_squares' path (its SVD follows the BLAS kernel).
    A penalty polish ends just outside a binding constraint; here it binds exactly. None
    when it does not converge or the budget has no room (evaluations counted against
    `counter`). With free timing each input angle moves its own pose's residuals and
    constraints alone: the differenced Hessian takes the angles together (kkt groups),
    two gradients for all of them instead of two each (scaling.py's 100 poses: the settles
    15.6 -> 2.8 s). The Hessian is Gauss-Newton's, and the differenced one of the whole
    Lagrangian only where the steps stall (kkt, curvature="stalled"): the constraints'
    curvature added at every step cost 10 % of a run's time (interleaved whole runs of tuning
    cases 3, 19, 35, 67, 91, 123 timed by benchmarks/compare_commands.py: 0.90) for the same
    verdicts on the tuning half."""
    from linkcli.search import kkt
    from linkcli.search.budget import BudgetSpent

    width = hi[mask] - lo[mask]

    def values(u):
        counter.spend(len(u))
        z = lo[mask] + np.clip(u, 0.0, 1.0) * width
        r = fun(z)
        return r if cons is None else np.concatenate([r, -cons(z) / scale], -1)

    m = len(fun(x[mask]))

    def points(us, gauss_newton: bool):  # the Points of unit-box points (K, n), one batch of residuals;
        # the Gauss-Newton matrix only where Newton steps from them (not at the Hessian's differenced points)
        v, jac = kkt.slopes_many(values, us, step=SETTLE_STEP)
        return kkt.least_squares_points(v, jac, m, gauss_newton)

    def evaluate(u):
        return points(np.asarray(u, float)[None, :], True)[0]

    def evaluate_many(us):
        return points(us, False)

    try:
        n_link = int(np.sum(mask[:10]))
        angles = [np.arange(n_link, len(width))] if free_timing and len(width) - n_link > 1 else []
        groups = [np.array([j]) for j in range(n_link if angles else len(width))] + angles
        u0 = (x[mask] - lo[mask]) / width
        out = kkt.settle(evaluate, u0, hessian_step=CURVATURE_STEP, curvature="stalled",
                         groups=groups, evaluate_many=evaluate_many)
        if not out.converged:  # not near a KKT point: walk there, settle again
            out = kkt.settle(evaluate, _walk(values, m, u0, scale), hessian_step=CURVATURE_STEP,
                             curvature="stalled", groups=groups, evaluate_many=evaluate_many)
    except BudgetSpent:
        return None
    if not out.converged:
        return None
    x = x.copy()
    x[mask] = lo[mask] + out.u * width
    return x


class _Walk:
    """The settle's residuals and constraints (`values` of unit-box points: the m residuals,
    then the constraints c >= 0) as linkcli.search.polish's problem: f = |r|^2, the exact
    penalty f + weight sum max(0, -c) its merit."""

    def __init__(self, values, m: int, n: int, weight: float):
        self.values, self.m, self.n_variables, self.weight = values, m, n, weight

    def value(self, u):
        v = self.values(np.asarray(u, float)[None, :])[0]
        r = v[:self.m]
        return float(r @ r), v[self.m:], r

    def slope(self, u, central=True):
        from linkcli.search import kkt
        v, jac = kkt.slopes_many(self.values, np.asarray(u, float)[None, :], step=SETTLE_STEP)
        r, jr = v[0, :self.m], jac[0, :self.m]
        return 2.0 * (jr.T @ r), jac[0, self.m:], jr


def _walk(values, m: int, u0, scale: float):
    """Where linkcli.search.polish's constrained Levenberg-Marquardt (`gauss_newton`:
    Gauss-Newton SQP steps on the constraints' linearization, inequalities and the box
    exact, second-order corrections) ends from u0: the settle's start when a Newton settle
    from the polished design failed. A penalty polish can stop far from the constrained
    optimum along a long, curved, ill-conditioned valley (motion study case 103, a
    transmission window: ended at 0.02047 with the reduced gradient 0.084 where the
    reduced Hessian's eigenvalues span 0.02 to 5e5; the optimum, 0.012050, lies 0.63 of
    the unit box away, and Newton's steps on a fixed active set overshoot there). The
    exact penalty's weight: 20 sqrt(f) L, ten times the size of a multiplier (a unit change
    of a constraint, c is dimensionless, moves the residuals by about L, and f by about
    2 sqrt(f) L). Its steps use numpy's BLAS and LAPACK (the house NNLS: scipy stays
    unloaded); the Newton settle after it brings the end to the same digits on every machine."""
    from linkcli.search import polish
    from linkcli.search.nnls import nnls
    f0 = float(np.sum(values(np.asarray(u0, float)[None, :])[0, :m] ** 2))
    problem = _Walk(values, m, len(u0), 20.0 * math.sqrt(max(f0, 0.0)) * scale + 1e-300)
    try:
        with np.errstate(all="ignore"):
            return polish.gauss_newton(problem, u0, nnls=nnls)
    except (ArithmeticError, ValueError, np.linalg.LinAlgError):  # a model that overflowed: no walk
        return u0


def _evaluate(x, poses, sign, weight, t_angles, grashof, transmission) -> dict:
    p = x[:10]
    phi = kin.wrap(x[10:] if t_angles is None else t_angles + x[10])
    ach, valid = assemble.body_poses(p, phi, sign)
    pos, ang = assemble.pose_errors(poses, ach)
    objective = float(np.sum(pos ** 2 + (weight * ang) ** 2))
    checks = assemble.check_linkage(p[4], p[5], p[6], p[3], phi, np.full(len(phi), sign))
    why = []
    if not np.all(valid):
        why.append("does not assemble at every pose")
    why += [f"{d} defect" for d in checks["defects"]]
    if grashof is not None and checks["grashof"]["class"] != grashof:
        why.append(f"Grashof class {checks['grashof']['class']}, not {grashof}")
    tol = design_constraints.WINDOW_TOL
    if transmission is not None and (checks["transmission_min"] < transmission[0] - tol
                                     or checks["transmission_max"] > transmission[1] + tol):
        why.append("transmission angle outside its bounds")
    return {"params": p, "branch": "open" if sign < 0 else "crossed", "input_angles": phi,
            "objective": objective, "achieved": ach, "position_error": pos, "angle_error": ang,
            "checks": checks, "feasible": not why, "why": "; ".join(why)}
