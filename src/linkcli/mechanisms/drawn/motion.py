"""The range of a drawn linkage's motion and the extremes of what it reports.

Reach. The leading drive's offset q from the drawing is followed both ways on a grid (every
GRID_DEG degrees of a turning drive, or the same share of a sliding drive's bound) as far as
every closure closes; the first failing offset each way is refined by k-section (KSECTION
points a round) to round-off: a dead point, where a closure locks (its two links in line;
a rod normal to its guide; a group whose Jacobian is singular). A turning drive that closes
on the whole turn turns fully. A grid point hides a gap in the motion narrower than its step
(documented: docs/drawn.md).

Extremes of a reported quantity f(q) (a transmission angle, a link angle, a slider's
place): the largest and smallest grid values, each refined by Newton's method on
df/dq = 0 within the neighbouring grid cells, f' = (df/dt) / q' and f'' = (d2f/dt2) / q'^2 at
a constant drive speed q'; the range's ends are candidates too. The location is exact to
round-off (not to the square root of it, as a search on the values would be).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkcli.mechanisms.drawn.groups import bound
from linkcli.mechanisms.drawn.model import TURN
from linkcli.mechanisms.drawn.vectors import cross, dot

TWO_PI = 2.0 * math.pi
GRID_DEG = 0.25  # reach and extremes: grid step of a turning drive (deg)
KSECTION = 16  # points a round when refining a dead point
ROUNDS = 14  # 16^14 > 7e16: to round-off from a grid cell
NEWTON_STEPS = 12
BISECTIONS = 80
TIE_GRID = 1e-6  # grid extremes this close to the best are refined too (a tie may hide there)
MAX_CANDIDATES = 3


@dataclass(frozen=True)
class Reach:
    """How far the leading drive moves from the drawing: offsets [lo, hi] (rad or length);
    `full_turn` (a turning drive closing all the way round: then lo, hi = 0, 2 pi);
    `locks` the closure that locks at each end (index into the plan, or None where the
    search bound stopped it)."""

    full_turn: bool
    lo: float
    hi: float
    locks: tuple[int | None, int | None]


def grid_step(kin) -> float:
    turning = kin.drawing.drives[0].kind == TURN
    return math.radians(GRID_DEG) if turning else bound(kin) * GRID_DEG / 360.0


def reach(kin) -> Reach:
    """The drive's reach (module docstring)."""
    limit = bound(kin)
    step = grid_step(kin)
    count = int(round(limit / step))
    q = np.linspace(-limit, limit, 2 * count + 1)
    st = kin.run(q, rates=False)
    ok = st.valid
    zero = count
    if not ok[zero]:  # the drawing itself: closes by construction
        ok[zero] = True
    turning = kin.drawing.drives[0].kind == TURN
    if turning and ok[zero:zero + int(round(TWO_PI / step)) + 1].all():
        return Reach(True, 0.0, TWO_PI, (None, None))
    ends, locks = [], []
    for direction in (-1, 1):
        k = zero
        while 0 <= k + direction < len(q) and ok[k + direction]:
            k += direction
        if not 0 <= k + direction < len(q):
            ends.append(q[k])
            locks.append(None)
            continue
        end, op = _ksection(kin, q[k], q[k + direction])
        ends.append(end)
        locks.append(op)
    return Reach(False, ends[0], ends[1], tuple(locks))


def _ksection(kin, good: float, bad: float) -> tuple[float, int | None]:
    """The last offset that closes between `good` (closes) and `bad` (does not), and the op
    whose closure fails just beyond it."""
    for _ in range(ROUNDS):
        points = good + (bad - good) * np.arange(1, KSECTION + 1) / (KSECTION + 1)
        st = kin.run(points, rates=False)
        fails = np.flatnonzero(~st.valid)
        first = fails[0] if fails.size else KSECTION
        if first > 0:
            good = points[first - 1]
        if first < KSECTION:
            bad = points[first]
        if abs(bad - good) <= 4 * np.spacing(max(abs(good), abs(bad), 1.0)):
            break
    st = kin.run(np.array([bad]), rates=False)
    op = next((k for k, rows in st.failed.items() if rows.any()), None)
    return float(good), op


# ---------------------------------------------------------------- extremes

def extremes(evaluate, lo: float, hi: float, full_turn: bool, step: float, count: int,
             periodic: bool = False, key=None):
    """Per quantity (count of them): [min, q at min, max, q at max] over offsets [lo, hi]
    (module docstring), None where never defined. `evaluate(q)` -> (value, d/dq, d2/dq2),
    each (n, count), NaN where undefined. `periodic`: the quantities are angles, followed
    continuously over the grid (unwrapped) and reported in that continuous form. Every grid
    extreme within a relative TIE_GRID of the best is refined; refined values within
    noise.TIE of each other are a tie, won by the smallest `key(q)` (the sweep order)."""
    from linkcli.noise import TIE
    key = key or (lambda q: q)
    q, value = grid_values(evaluate, lo, hi, step, periodic)
    cells = len(q) - 1
    out, candidates = [], []
    for k in range(count):
        column = value[:, k]
        finite = np.isfinite(column)
        if not finite.any():
            out.append(None)
            continue
        out.append([math.inf, 0.0, -math.inf, 0.0])
        for sense in (-1.0, 1.0):
            signed = np.where(finite, sense * column, -np.inf)
            best = signed.max()
            near = np.flatnonzero(signed >= best - TIE_GRID * max(abs(best), 1e-300))
            candidates += [(k, int(i), sense) for i in near[:MAX_CANDIDATES]]
    if not candidates:
        return out
    starts = np.array([q[i] for _, i, _ in candidates])
    left = np.array([q[max(i - 1, 0)] for _, i, _ in candidates])
    right = np.array([q[min(i + 1, cells)] for _, i, _ in candidates])
    if full_turn:  # the cells wrap round
        left = np.where([i == 0 for _, i, _ in candidates], starts - (q[1] - q[0]), left)
        right = np.where([i == cells for _, i, _ in candidates], starts + (q[1] - q[0]), right)
    cols = np.array([k for k, _, _ in candidates])
    rows = np.arange(len(candidates))
    x = starts.copy()
    for _ in range(NEWTON_STEPS):
        _, d1, d2 = evaluate(x)
        with np.errstate(all="ignore"):
            nxt = x - d1[rows, cols] / d2[rows, cols]
        nxt = np.where(np.isfinite(nxt) & (nxt >= left) & (nxt <= right), nxt, x)
        if np.all(nxt == x):
            break
        x = nxt
    refined, _, _ = evaluate(x)
    for n_, (k, i, sense) in enumerate(candidates):
        v = refined[n_, k]
        if periodic:  # the refined angle on the grid's continuous branch
            v = v + TWO_PI * np.round((value[i, k] - v) / TWO_PI)
        if not np.isfinite(v) or sense * v < sense * value[i, k]:
            v, x[n_] = value[i, k], q[i]  # Newton wandered off: the grid value stands
        entry = out[k]
        at = 0 if sense < 0 else 2
        current = entry[at]
        if not math.isfinite(current) or sense * (v - current) > TIE * max(abs(v), abs(current)):
            entry[at], entry[at + 1] = float(v), float(x[n_])
        elif abs(v - current) <= TIE * max(abs(v), abs(current)) and key(x[n_]) < key(entry[at + 1]):
            entry[at], entry[at + 1] = float(v), float(x[n_])
    return out


def grid_values(evaluate, lo, hi, step, periodic=False):
    """(q, values) on the grid over [lo, hi] (angles unwrapped along it when `periodic`)."""
    cells = max(8, int(math.ceil((hi - lo) / step)))
    q = np.linspace(lo, hi, cells + 1)
    value, _, _ = evaluate(q)
    q, value = _ends_inside(evaluate, q, value, hi - lo)
    if periodic:
        value = value.copy()
        for k in range(value.shape[1]):
            finite = np.isfinite(value[:, k])
            value[finite, k] = np.unwrap(value[finite, k])
    return q, value


END_NUDGES = (1e-14, 1e-12, 1e-10, 1e-8)  # of the span: an end node moved inward until it assembles


def _ends_inside(evaluate, q, value, span: float):
    """The grid with an end node that does not assemble where its neighbour does moved inward
    by the least of END_NUDGES (of the span) that assembles: a rocking drive's range ends at
    a dead point, where the closure only just assembles and round-off in the place of the end
    can leave it not assembling (a cylinder's guide angle written to 11 digits lost the far
    end of its stroke: 89.1649 where the drive's range gave 89.4427, the last grid row before
    the end taken for it). The extremes and crossings then start from the end itself."""
    if len(q) < 3 or not span > 0.0:
        return q, value
    moves = []
    for end, inner, sense in ((0, 1, 1.0), (len(q) - 1, len(q) - 2, -1.0)):
        short = np.isfinite(value[inner]) & ~np.isfinite(value[end])
        if short.any():
            moves.append((end, inner, sense))
    if not moves:
        return q, value
    tries = np.array([q[end] + sense * f * span for end, _, sense in moves for f in END_NUDGES])
    tried, _, _ = evaluate(tries)
    q, value = q.copy(), value.copy()
    for m, (end, inner, _) in enumerate(moves):
        wanted = np.isfinite(value[inner])
        for t in range(len(END_NUDGES)):
            row = tried[m * len(END_NUDGES) + t]
            if np.all(np.isfinite(row[wanted])):
                q[end], value[end] = tries[m * len(END_NUDGES) + t], row
                break
    return q, value


def crossings(evaluate, q, value, columns) -> dict[int, list[float]]:
    """Per column in `columns`: the offsets where it changes sign on the grid (q, value),
    refined to round-off by Newton's method kept inside each bracket by bisection."""
    brackets = []
    for k in columns:
        v = value[:, k]
        ok = np.isfinite(v[:-1]) & np.isfinite(v[1:])
        idx = np.flatnonzero(ok & ((np.sign(v[:-1]) != np.sign(v[1:])) | (v[:-1] == 0)))
        brackets += [(k, q[i], q[i + 1], v[i]) for i in idx]
    out: dict[int, list[float]] = {k: [] for k in columns}
    if not brackets:
        return out
    cols = np.array([b[0] for b in brackets])
    a = np.array([b[1] for b in brackets])
    b = np.array([b[2] for b in brackets])
    fa = np.sign(np.array([b_[3] for b_ in brackets]))
    rows = np.arange(len(brackets))
    x = 0.5 * (a + b)
    for _ in range(BISECTIONS):
        f, d1, _ = evaluate(x)
        fx, dx = f[rows, cols], d1[rows, cols]
        same = np.sign(fx) == fa
        a, b = np.where(same, x, a), np.where(same, b, x)
        with np.errstate(all="ignore"):
            newton = x - fx / dx
        x_new = np.where(np.isfinite(newton) & (newton > np.minimum(a, b)) & (newton < np.maximum(a, b)),
                         newton, 0.5 * (a + b))
        x_new = np.where(fx == 0, x, x_new)
        if np.all(x_new == x):
            break
        x = x_new
    for n_, k in enumerate(cols):
        out[int(k)].append(float(x[n_]))
    return out


# ---------------------------------------------------------------- closures

def closure_vectors(kin, st, closure):
    """(a, a', a'', b, b', b'') of a closure (structure.Closure) over the state's rows: "pin":
    a = first - joint, b = second - joint; "guide": a = the guide's direction, b = joint -
    first (the arm). None for the rates of a state without them."""
    j = closure.joint
    if closure.kind == "pin":
        return _rel(st, closure.first, j) + _rel(st, closure.second, j)
    _, u, body = kin.guide_line(st, j)
    if not st.rates:
        return (u, None, None) + _rel(st, j, closure.first)
    w, al = st.omega[body][:, None], st.alpha[body][:, None]
    pu = np.stack([-u[:, 1], u[:, 0]], axis=-1)
    return (u, w * pu, al * pu - w * w * u) + _rel(st, j, closure.first)


def _rel(st, tip, tail):
    """tip - tail with its rates."""
    d = st.pos[tip] - st.pos[tail]
    if not st.rates:
        return d, None, None
    return d, st.vel[tip] - st.vel[tail], st.acc[tip] - st.acc[tail]


def transmission(kind: str, a, da, dda, b, db, ddb):
    """(mu, mu', mu'') of a closure: "pin": the angle between a and b in [0, pi]
    (mu = |wrap(arg b - arg a)|); "guide": mu = arccos(|u x r| / |r|) in [0, pi/2] (90 deg is
    ideal: the force along the guide's normal and the arm r at right angles, as the
    slider-crank's)."""
    from linkcli.mechanisms.drawn.vectors import direction_rates
    if da is None:
        psi = np.arctan2(cross(a, b), dot(a, b))
        return (np.abs(psi), None, None) if kind == "pin" else (0.5 * np.pi - np.abs(_half(psi)), None, None)
    pa, wa, aa = direction_rates(a, da, dda)
    pb, wb, ab = direction_rates(b, db, ddb)
    psi = np.arctan2(cross(a, b), dot(a, b))
    if kind == "pin":
        s = np.sign(psi)
        return np.abs(psi), s * (wb - wa), s * (ab - aa)
    half = _half(psi)
    s = np.sign(half)
    return 0.5 * np.pi - np.abs(half), -s * (wb - wa), -s * (ab - aa)


def _half(psi):
    """psi folded into [-pi/2, pi/2] (a line's direction is defined up to pi)."""
    return psi - np.pi * np.round(psi / np.pi)
