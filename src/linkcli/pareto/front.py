"""The front: an epsilon-constraint sweep over the type's design space (docs/pareto.md).

1. Anchors. The type's own least-squares design x0 (found and confirmed by its own search) is
   the anchor of `error`; each other objective's anchor minimizes it from x0 (linkcli.pareto.
   scalarized, its pieces in epigraph form).
2. Levels. Two objectives: `points` levels of the second, evenly spaced from its value at
   the first's anchor to ANCHOR_GAP of its scale above its best (that level's point stands for
   the second's anchor: the least first objective within the gap of the second's least, and
   the anchor itself is no row then: `refines`). Three: a grid of ceil(sqrt(points)) levels
   each of the second and the third, from their worst over the anchors to ANCHOR_GAP above
   their best (the payoff table); a level that no design reaches gives no point. The gap is
   what makes the end a well-posed level: at the best itself (or 1e-7 of it) the level's
   feasible set is a sliver, the designs it holds differ from the anchor's binding set by less
   than the settle resolves (a length 6e-8 of its range off its bound is read as on it, and
   the multiplier of that bound has the wrong sign), and the end printed the polish's digits.
3. Points. At each level, the first objective minimized subject to the others <= their levels
   and every constraint of the file. Each row of levels is swept by two chains, one from
   each end (continuation: each level polished from the chain's last end, a few Gauss-Newton
   steps where a level is near the last; the two chains are independent solves, spread over
   processes or a cluster by linkcli.pareto.spread). The lower feasible end is the point
   (the front often has branches: a chain follows one, the other chain another), and it
   alone is settled (`settle_point`: Newton-KKT to round-off, the printed digits the same on
   every machine); `certified` when its polish ended at a KKT point (SLSQP's test) or its
   settle converged, `confirmed` when both chains ended within CONFIRM of it.
4. Rows. Each point's design is finished by the type (`space.final`: its exact checks of
   every constraint, from its lengths) and measured again (linkcli.pareto.objectives); a
   design that is not `ok` or not finite is dropped, as is one dominated by another (after
   the values are rounded to the noise floor: TIE relative), and a duplicate. The rows are
   ordered by the first objective, then the second (the third).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkcli.pareto.objectives import Measure
from linkcli.pareto.scalarized import Scalarized
from linkcli.search.budget import Budget, BudgetSpent

ANCHOR_GAP = 1e-5  # of an objective's scale: the front's end is its level this far above its best (2.;
# path_pareto's end settles from 1e-6 to 1e-3 of the range and fails at the 2e-8 of 1e-7 of its value)
SAME = 1e-7  # relative: two solves that end at one design agree within this (`non_dominated`)
CONFIRM = 1e-6  # relative (of the first objective's scale): two starts that end this close agree
TIE = 1e-9  # relative to an objective's scale: values this close are equal (dominance, order)
FEASIBLE = 1e-7  # a scaled constraint this far below 0 is still met (the type's final check decides)
POINT_BUDGET = 20_000  # design evaluations of one start's polish, at most
ACTIVE = 1e-6  # a scaled constraint (or unit-box variable) this close to its limit binds (kkt_holds)
KKT_TOL = 1e-4  # relative: the first-order conditions' residual of a certified point (kkt_holds)
SETTLE_STEP = 1e-4  # unit box: the differenced Hessian's step (kkt.settle)
SETTLE_STEP_TOL = 1e-8  # unit box: a Newton step this small ends the settle. The slopes (central
# differences of the refined size pieces, round-off ~1e-13 relative, at CENTRAL = 1e-6) leave steps
# of 1e-10 to 2e-9 that never shrink further (the 10-point path's front); the printed digits (6
# significant) resolve 1e-5 of a value, 1e-4 to 1e-5 of a bound's width: 1e-8 settles them
SETTLED_FEASIBLE = 1e-10  # a settled point meets its (scaled) constraints to this
ROUND_OFF = 1e-9  # relative: a certified end this close to the best merit seen is taken
EPIGRAPH_ITERATIONS = 100  # SLSQP's, an epigraph's polish
EPIGRAPH_FTOL = 1e-9  # SLSQP's tolerance on t (t in [0, 1] spans twice the objective's scale)
SCALE_FLOOR = 1e-12  # relative: an objective with no spread over the anchors is scaled by its size
UNMEASURED = (IndexError,)  # a design whose objective has fewer pieces than its neighbours' (the
# transmission of a linkage that does not assemble: one infinite piece) ends a Newton settle


@dataclass
class Point:
    """One solve's end: design x, its values, the start it came from and the polish's verdict."""

    x: np.ndarray
    values: np.ndarray
    start: int
    certified: bool
    confirmed: bool = False
    level: tuple = ()


@dataclass
class Task:
    """One chain of levels, picklable: the measure (problem and space), the primary
    objective, the scales, the epigraph's t scale, the levels in the order the chain
    solves them ((index, {objective: level}) each) and the design it starts from."""

    measure: Measure
    primary: int
    scales: np.ndarray
    t_scale: float
    levels: list
    start: np.ndarray
    chain: int


def polish_from(problem: Scalarized, x) -> tuple[np.ndarray, bool]:
    """(design, certified) from design x: linkcli.search.polish's Gauss-Newton SQP steps,
    then SLSQP to certify a KKT point (a least-squares primary: polish.slsqp_rounds, in the
    coordinates of its Gauss-Newton Hessian; an epigraph, whose residual t has no curvature
    in the design: SLSQP on the unit box itself, `epigraph_slsqp`). The better end by the
    exact penalty merit is kept (a spent budget: the best point reached)."""
    from linkcli.search import polish
    u0 = problem.unit(x, t=None)
    if problem.epigraph:
        u0[-1] = min(1.0, problem.objective(u0) / (problem.scales[problem.primary] * problem.t_scale))
    tried = [u0]
    certified = False
    try:
        with np.errstate(all="ignore"):
            if problem.epigraph:  # no Gauss-Newton model: t alone has curvature
                u1 = u0
                u2, certified = epigraph_slsqp(problem, u0)
            else:
                u1 = polish.gauss_newton(problem, u0)
                tried.append(u1)
                last = {}
                value = problem.value

                def tracked(u):  # slsqp_rounds evaluates its end point last
                    last["u"] = np.asarray(u, float).copy()
                    return value(u)

                problem.value = tracked
                try:
                    certified = polish.slsqp_rounds(problem, u1)
                finally:
                    problem.value = value
                u2 = last.get("u", u1)
            tried.append(u2)
    except (BudgetSpent, ArithmeticError, ValueError, np.linalg.LinAlgError, *UNMEASURED):
        certified = False
    merits = [problem.merit(u) for u in tried]
    k = int(np.argmin(merits))
    if len(tried) >= 2 and certified and merits[-1] <= merits[k] + ROUND_OFF * max(abs(merits[k]), 1e-300):
        k = len(tried) - 1  # SLSQP's certified end, as good as the best within round-off
    else:  # SLSQP stopped by its own limits, or an earlier end is better: the first-order
        certified = len(tried) >= 2 and kkt_holds(problem, tried[k])  # conditions checked here
    u = tried[k]
    return problem.design(u), bool(certified) and problem.feasible(u, FEASIBLE)


def kkt_holds(problem: Scalarized, u) -> bool:
    """Whether u is a KKT point of its level to within KKT_TOL: feasible (FEASIBLE), and the
    objective's gradient a nonnegative combination of the gradients of the constraints and
    bounds that bind there (within ACTIVE): nonnegative least squares for the multipliers
    (linkcli.search.nnls), its residual at most KKT_TOL of the gradient (central differences)."""
    from linkcli.search.nnls import nnls
    f, c, _ = problem.value(u)
    if not np.all(c >= -FEASIBLE):
        return False
    g, jc, _ = problem.slope(u, central=True)
    if problem.epigraph:
        g = np.zeros_like(g)
        g[-1] = 1.0
    n = len(u)
    normals = [jc[c <= ACTIVE]]
    eye = np.eye(n)
    normals.append(eye[u <= ACTIVE])  # a variable at its lower bound: u_i >= 0
    normals.append(-eye[u >= 1.0 - ACTIVE])
    a = np.vstack(normals)
    size = float(np.max(np.abs(g)))
    if not size > 0:
        return True
    if not len(a):
        return False
    try:
        lam, _ = nnls(a.T / size, g / size)
    except RuntimeError:
        return False
    residual = float(np.max(np.abs(a.T @ lam - g) / size))
    return residual <= KKT_TOL


def settle(problem: Scalarized, x) -> tuple[np.ndarray, bool]:
    """(design, settled): Newton on the KKT system of the constraints that bind at design x
    (linkcli.search.kkt: the house's linear algebra, no BLAS), to round-off, so that the
    printed digits are the level's optimum's and not those of the polish's path (SLSQP's
    tolerance on f leaves a flat direction's digits to the machine). A least-squares first
    objective: the Gauss-Newton Hessian, differenced where the steps stall; an epigraph: the
    Lagrangian's Hessian by differences at least-squares multipliers. The end is taken when it
    converged, meets every constraint of the level and is no worse (merit, within ROUND_OFF).
    Where that settle fails on a level that holds the size, the level is settled again with its
    size lifted (Scalarized.lifted: the box's sides as variables, each beyond every peak of every
    joint): where joints tie for a side of the box, or a joint's coordinate peaks twice over the
    motion, the pieces of the max bind together with dependent gradients, or one piece bends,
    and the active set cycles."""
    end, settled = _settle(problem, problem, x)
    if settled:
        return end, True
    lifted = problem.lifted(x)
    if lifted is problem:
        return end, False
    return _settle(problem, lifted, x)


def _settle(problem: Scalarized, form: Scalarized, x) -> tuple[np.ndarray, bool]:
    """`settle` of problem's level from design x in the variables of `form` (the problem itself,
    or its size lifted: its design variables, and t, first)."""
    from linkcli.search import kkt
    u0 = problem.unit(x, t=None)
    if problem.epigraph:
        u0[-1] = min(1.0, problem.objective(u0) / (problem.scales[problem.primary] * problem.t_scale))
    start = form.unit(x, t=None)
    start[:len(u0)] = u0

    def evaluate(u):
        f, c, r = form.value(u)
        g, jc, jr = form.slope(u, central=True)
        return kkt.Point(f, g, c, jc, h=None if form.epigraph else 2.0 * (jr.T @ jr))

    def evaluate_many(us):  # the differenced Hessian's points: forward slopes (n + 1 designs, not
        # 2n + 1); their error (~1e-6 relative) costs Newton's rate 1e-2 a step, not its root
        form.prefetch(us, central=False)  # every design of the n + 1 slopes in one batch
        out = []
        for u in us:
            f, c, _ = form.value(u)
            g, jc, _ = form.slope(u, central=False)
            out.append(kkt.Point(f, g, c, jc))
        return out

    try:
        with np.errstate(all="ignore"):
            out = kkt.settle(evaluate, start, hessian_step=SETTLE_STEP, multipliers=True, step_tol=SETTLE_STEP_TOL,
                             curvature=False if form.epigraph else "whole", reuse=True,
                             evaluate_many=evaluate_many)
    except (BudgetSpent, ArithmeticError, ValueError, np.linalg.LinAlgError, *UNMEASURED):
        return np.asarray(x, float), False
    end = out.u[:len(u0)]  # the design (and t), a lifted box's sides dropped
    if not (out.converged and problem.feasible(end, SETTLED_FEASIBLE)
            and problem.merit(end) <= problem.merit(u0) + ROUND_OFF * max(abs(problem.merit(u0)), 1e-300)):
        return np.asarray(x, float), False
    return problem.design(end), True


def epigraph_slsqp(problem: Scalarized, u0) -> tuple[np.ndarray, bool]:
    """min t subject to the constraints (pieces <= t among them) and the unit box, by SLSQP
    (Kraft 1988) with forward-difference slopes; (end, converged)."""
    from scipy.optimize import minimize
    n = problem.n_variables
    last = np.zeros(n)
    last[-1] = 1.0
    res = minimize(lambda u: float(u[-1]), u0, jac=lambda u: last, method="SLSQP",
                   bounds=[(0.0, 1.0)] * n,
                   constraints=[{"type": "ineq", "fun": lambda u: problem.value(np.clip(u, 0, 1))[1],
                                 "jac": lambda u: problem.slope(np.clip(u, 0, 1), central=False)[1]}],
                   options={"maxiter": EPIGRAPH_ITERATIONS, "ftol": EPIGRAPH_FTOL})
    u = np.clip(res.x, 0.0, 1.0)
    problem.value(u)
    return u, bool(res.success)


def solve_chain(task: Task) -> tuple[list, int]:
    """A chain's levels in turn, each polished from the last feasible end before it (the
    chain's start at first): continuation along the front (top-level: another process or a
    cluster worker runs it). Returns (index, Point or None) per level, and the evaluations
    spent. The ends are not settled here: only each level's best end is (`settle_point`),
    once the chains are compared (the settle costs ten times the polish)."""
    budget = Budget(POINT_BUDGET * max(1, len(task.levels)))
    out = []
    x = np.asarray(task.start, float)
    for index, eps in task.levels:
        problem = Scalarized(task.measure, task.primary, eps, task.scales, budget)
        problem.t_scale = task.t_scale
        with budget.limit(POINT_BUDGET), np.errstate(all="ignore"):
            end, certified = polish_from(problem, x)
        u = problem.unit(end, t=1.0)
        values = task.measure.values(end)
        if not (problem.feasible(u, FEASIBLE) and np.all(np.isfinite(values))):  # (the failure
            # probability is held by its smoothed share: its exact value may differ a little)
            out.append((index, None))
            continue
        out.append((index, Point(end, values, task.chain, certified, level=tuple(sorted(eps.items())))))
        x = end
    return out, budget.used


@dataclass
class Settle:
    """One level's best end to settle, picklable: the measure, the primary objective, the
    scales, the epigraph's t scale and the Point (its `level` the epsilon levels)."""

    measure: Measure
    primary: int
    scales: np.ndarray
    t_scale: float
    point: Point


def settle_point(task: Settle) -> tuple[Point, int]:
    """A level's best end settled to round-off (`settle`: the same digits whatever the
    machine) and measured again. A settle that converged ends at a KKT point of the level
    (Newton-KKT's residual at round-off, multipliers of the right sign, feasible, no worse):
    the point is then certified even where the polish stopped short of its own test. An
    end whose settle fails stays as it was. Returns (Point, evaluations spent)."""
    p = task.point
    budget = Budget(POINT_BUDGET)
    problem = Scalarized(task.measure, task.primary, dict(p.level), task.scales, budget)
    problem.t_scale = task.t_scale
    with np.errstate(all="ignore"):
        end, settled = settle(problem, p.x)
        values = task.measure.values(end) if settled else p.values
    if not (settled and problem.feasible(problem.unit(end, t=1.0), FEASIBLE) and np.all(np.isfinite(values))):
        return p, budget.used
    return Point(end, values, p.start, True, p.confirmed, p.level), budget.used


def best_of(points: list[Point], primary: int, scale: float) -> Point | None:
    """The lowest first objective (ties within TIE: the earlier chain); `confirmed` when
    another chain ended within CONFIRM of it."""
    finite = [p for p in points if np.all(np.isfinite(p.values))]
    if not finite:
        return None
    low = min(p.values[primary] for p in finite)
    best = min((p for p in finite if p.values[primary] <= low + TIE * scale), key=lambda p: p.start)
    best.confirmed = sum(abs(p.values[primary] - best.values[primary]) <= CONFIRM * scale for p in finite) >= 2
    return best


def scales_of(values: np.ndarray) -> np.ndarray:
    """Per objective, its spread over the anchors (rows of `values`), or its size."""
    spread = values.max(axis=0) - values.min(axis=0)
    size = np.max(np.abs(values), axis=0)
    return np.where(spread > SCALE_FLOOR * np.maximum(size, 1e-300), spread, np.maximum(size, 1.0))


def levels(anchor_values: np.ndarray, points: int, scales) -> list[list[dict]]:
    """The epsilon levels (module docstring, 2.) as rows of {objective index: level}, each
    row ordered from loose to tight in its last objective: two objectives, one row evenly
    from the second's value at the first's anchor to its best, the last level ANCHOR_GAP of
    its scale above the best (there the level's point stands for the second's anchor:
    `refines`); three, one row per level of the second, each spanning the third's range over
    the anchors (the same way)."""
    m = anchor_values.shape[1]

    def span(k: int, top: float, best: float, count: int) -> np.ndarray:  # evenly from the top to the
        # best (held within SAME: one design found twice), the last level ANCHOR_GAP above the best
        out = np.linspace(top, best + SAME * abs(best) + TIE * scales[k], count)
        out[-1] = min(best + ANCHOR_GAP * scales[k], top)
        return out

    if m == 2:
        return [[{1: float(v)} for v in span(1, anchor_values[0, 1], anchor_values[1, 1], points)]]
    side = max(2, int(math.ceil(math.sqrt(points))))
    grid = [span(k, anchor_values[:, k].max(), anchor_values[:, k].min(), side) for k in (1, 2)]
    return [[{1: float(a), 2: float(b)} for b in grid[1]] for a in grid[0]]


def chains(rows: list[list[dict]], anchors: list[np.ndarray]) -> list[tuple[list, np.ndarray]]:
    """Each row of levels solved by two chains, one from each end: loose to tight from the
    first objective's anchor, tight to loose from the last objective's (so every level is
    reached from two sides; where they end within CONFIRM, it is `confirmed`). Levels are
    numbered across the rows."""
    out, index = [], 0
    for row in rows:
        numbered = list(enumerate(row, start=index))
        index += len(row)
        out.append((numbered, anchors[0]))
        out.append((numbered[::-1], anchors[-1]))
    return out


def refines(anchor: Point, k: int, points: list[Point], scales) -> bool:
    """Whether a certified point of the front stands for objective k's anchor: within
    ANCHOR_GAP of its scale of the anchor's value of k (twice: the level's own round-off) and
    no worse in every other objective (within TIE): the point of the anchor's end level (2.),
    where the least first objective was sought near the least k. The anchor (the least k found
    from the first objective's anchor, its other objectives wherever that search stopped) is
    then no row; where that point is not certified, the anchor stays (`non_dominated` keeps
    the first of two equal points: the anchor)."""
    scales = np.asarray(scales, float)
    near = TIE * scales
    near[k] = 2.0 * ANCHOR_GAP * scales[k]
    return any(p.certified and np.all(p.values <= anchor.values + near)
               for p in points if np.all(np.isfinite(p.values)))


def dominates(a: np.ndarray, b: np.ndarray, tol: np.ndarray) -> bool:
    """a is no worse than b in every objective and better in one (beyond tol)."""
    return bool(np.all(a <= b + tol) and np.any(a < b - tol))


def non_dominated(points: list, values, scales) -> list:
    """The points no other dominates (values compared within TIE of each scale and twice
    SAME of their size: the first objective's anchor and its own level's point are one design
    found twice), duplicates (every value within that) kept once: the first in order."""
    values = np.asarray(values, dtype=float)
    tol = TIE * np.asarray(scales)
    keep = []
    for i, v in enumerate(values):
        near = tol + 2.0 * SAME * np.abs(v)
        if any(dominates(values[j], v, near) for j in range(len(values)) if j != i):
            continue
        if any(np.all(np.abs(values[j] - v) <= near) for j in keep):
            continue
        keep.append(i)
    return [points[i] for i in keep]
