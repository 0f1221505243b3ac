"""The geometry of the catalogue's starting drawings (docs/six_bars.md): joint places of one
assembly whose crank turns fully with every closure away from its dead points, over SAMPLES
crank angles (row 0: the drawing), keyed by the chain's pins (pairs of links) and "P", "Q"
(the tracer; the body's frame).

- Four-bar and dyad (a four-bar loop holds ground and drive): a Grashof crank-rocker, crank
  shortest (ground 1), transmission mu = arccos((b^2 + c^2 - (1 -+ a)^2) / (2 b c)) within
  [MU_FOUR, 180 - MU_FOUR] at its extremes (crank along the ground line); the dyad's two
  links (l1, l2 = rho l1) join a point X of one body of the four-bar to a point Y of another,
  |X - Y| = d between d_min and d_max over the turn; its transmission angle,
  cos mu = (l1^2 + l2^2 - d^2) / (2 l1 l2), stays within [MU_DYAD, 180 - MU_DYAD] when
  d_max / sqrt(1 + rho^2 + 2 rho cos MU_DYAD) <= l1 <= d_min / sqrt(1 + rho^2 - 2 rho cos MU_DYAD).
- Triad, driven at an end of the path T - p - p' - T' (Stephenson's chain: T, T' its ternary
  links, also joined by the four-bar loop T - qa - T' - qb; p or T the ground): in T's frame
  a Grashof four-bar with qa its crank moves the pin E of T' along a closed curve; the crank
  p (radius r, about a pin of T) drives E through the rod p' (length L = 2 to 3.5 r) drawn in
  line with E's path (a slider-crank on a curved guide), where E's curve bends least among
  the places whose closures are open by MU_NODE. Checked on the rows: for every crank angle
  exactly one place within 2.5 r of arc of the drawn one is at L from the crank pin, the
  window's ends never are, and the rod is within 60 deg of E's path there (TRIAD_INDEX =
  cos 60 deg); else a shorter crank (r from 0.9 to 0.25 of the bend's radius, at most an
  eighth of the curve).
- Triad, driven in the middle of the path (p - p', the ground and the crank): in the frame
  of Tg (the ternary pinned to the ground) the same four-bar moves the pin E of Tk; rho =
  |E - O1| (O1 Tg's pivot) rises (or falls) over a stretch of E's curve on which
  |d rho| >= TRIAD_INDEX |dE| and the closures are open. A crank of radius r below
  (rho_hi - rho_lo) / 2, centred at (rho_lo + rho_hi) / 2 from O1, meets that stretch at one
  place for every angle, and Tg turns to bring E there: exact, by construction.

Every candidate is then checked on its rows: each closure linkcli measures (`keep`, from
structure.Closure) within [MU_CLOSURE, 180 - MU_CLOSURE]. Of the first CANDIDATES that pass,
the one scoring best (`score`: a compact linkage for its tracer's path, a wide output swing)
is kept. Places between the inner four-bar's grid angles are interpolated (rows used for the
checks and the fit only; row 0 is exact). Trigonometry only through `math` on a few angles
and exact rotations, so that a seed draws the same places on every CPU (numpy's vector sin
and cos may differ in the last bit between CPUs).
Sources: Norton, Design of Machinery, ch. 2 and 4 (Grashof's condition, transmission
angle); Hartenberg & Denavit, Kinematic Synthesis of Linkages (the six-bar chains).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

SAMPLES = 360  # crank angles checked and fitted (1 deg)
GRID = 720  # the inner four-bar's crank angles (triads)
COARSE = 5  # a triad's crank rows tried first: every fifth
MU_FOUR = math.radians(40.0)  # four-bar loops: transmission within [40, 140] deg
MU_DYAD = math.radians(35.0)  # dyads: within [35, 145] deg
TRIAD_INDEX = 0.5  # triads: the closing link within 60 deg of the motion it drives
MU_CLOSURE = math.radians(30.0)  # every closure linkcli measures: within [30, 150] deg over the turn
MU_NODE = math.radians(40.0)  # a triad's drawn place: its closures within [40, 140] deg there
MAX_ATTEMPTS = 1000  # draws per drawing before giving up (one in two or three is taken)
FOUR_BAR_DRAWS = 64  # four-bar proportions drawn at once
CANDIDATES = 4  # candidates a drawing is chosen from (the best score)
GOOD = {"path": 0.45, "motion": 0.45, "function": 1.0}  # a candidate scoring this is taken at once
SWING_FULL = math.radians(75.0)  # a function's output swinging this far scores 1
SQRT_HALF = math.sqrt(0.5)
ROTATIONS = ((1.0, 0.0), (SQRT_HALF, SQRT_HALF), (0.0, 1.0), (-SQRT_HALF, SQRT_HALF),
             (-1.0, 0.0), (-SQRT_HALF, -SQRT_HALF), (0.0, -1.0), (SQRT_HALF, -SQRT_HALF))
DIGITS = 9  # significant digits of a drawn coordinate, relative to the box's size


# ---------------------------------------------------------------- vectors

@lru_cache(maxsize=4)
def _unit_circle(n: int) -> np.ndarray:
    """(cos, sin) of 2 pi k / n, k = 0 .. n - 1, by `math` (the same bits on every CPU)."""
    return np.array([(math.cos(2.0 * math.pi * k / n), math.sin(2.0 * math.pi * k / n)) for k in range(n)])


def _perp(v: np.ndarray) -> np.ndarray:
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


def _dot(u, v):
    return u[..., 0] * v[..., 0] + u[..., 1] * v[..., 1]


def _cross(u, v):
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def _turned(v: np.ndarray, by: np.ndarray) -> np.ndarray:
    """v rotated by the angles whose (cos, sin) rows are `by`."""
    return np.stack([by[..., 0] * v[..., 0] - by[..., 1] * v[..., 1],
                     by[..., 1] * v[..., 0] + by[..., 0] * v[..., 1]], axis=-1)


def _circles(p1, r1, p2, r2, side):
    """The point J with |J - p1| = r1, |J - p2| = r2 on the side `side` (+1 left) of p1 -> p2,
    and where it exists."""
    d = p2 - p1
    rho2 = _dot(d, d)
    along = (r1 * r1 - r2 * r2 + rho2) / (2.0 * rho2)
    across2 = r1 * r1 / rho2 - along * along
    ok = across2 > 0.0
    across = np.sqrt(np.where(ok, across2, 0.0))
    return p1 + along[..., None] * d + (side * across)[..., None] * _perp(d), ok


def _local(origin, toward, u: float, v: float):
    """The point (u, v) of a body whose frame has its origin at `origin` and its x axis (of
    the body's length) towards `toward`."""
    d = toward - origin
    return origin + u * d + v * _perp(d)


def _sign(rng) -> float:
    return 1.0 if rng.random() < 0.5 else -1.0


def _edge(a: int, b: int) -> tuple[int, int]:
    return (min(a, b), max(a, b))


def _central(values: np.ndarray, step: float):
    """First and second derivatives of a periodic sampled curve (central differences)."""
    ahead, back = np.roll(values, -1, axis=0), np.roll(values, 1, axis=0)
    return (ahead - back) / (2.0 * step), (ahead - 2.0 * values + back) / (step * step)


def _fixed(point, like: np.ndarray) -> np.ndarray:
    """A fixed point as rows shaped like `like`."""
    return np.broadcast_to(np.asarray(point, dtype=float), like.shape)


def _along(points: np.ndarray, lo, hi, w: np.ndarray, exact: int) -> np.ndarray:
    """Rows between grid places lo and hi at fractions w (a column); row 0 the grid place
    `exact` itself (the drawing)."""
    out = points[lo] + w * (points[hi] - points[lo])
    out[0] = points[exact]
    return out


def open_rows(at: dict, keep, mu: float):
    """Per row, whether every closure of `keep` whose three pins `at` holds has its angle
    within [mu, 180 - mu]. keep: (first, joint, second) pins; the angle is the one at `joint`
    between the lines to `first` and `second` (structure.Closure). True when none is held."""
    limit, ok = math.cos(mu), True
    for first, joint, second in keep:
        if first in at and joint in at and second in at:
            a, b = at[first] - at[joint], at[second] - at[joint]
            ok = ok & (np.abs(_dot(a, b)) <= limit * np.sqrt(_dot(a, a) * _dot(b, b)))
    return ok


# ---------------------------------------------------------------- the four-bar loop

def crank_rocker(rng) -> tuple[float, float, float]:
    """(crank a, coupler b, rocker c) on a ground of 1: Grashof with the crank shortest (it
    turns fully), transmission within [MU_FOUR, 180 - MU_FOUR] (module docstring)."""
    limit = math.cos(MU_FOUR)
    for _ in range(100):  # a draw of 64 finds one nearly always (about a third pass)
        a = rng.uniform(0.2, 0.45, FOUR_BAR_DRAWS)
        b = rng.uniform(0.5, 1.8, FOUR_BAR_DRAWS)
        c = rng.uniform(0.45, 1.6, FOUR_BAR_DRAWS)
        longest = np.maximum(np.maximum(b, c), 1.0)
        others = 1.0 + b + c - longest
        grashof = (a < np.minimum(np.minimum(b, c), 1.0)) & (a + longest <= others - 0.05)
        lo = (b * b + c * c - (1.0 - a) ** 2) / (2.0 * b * c)
        hi = (b * b + c * c - (1.0 + a) ** 2) / (2.0 * b * c)
        ok = np.flatnonzero(grashof & (lo <= limit) & (hi >= -limit))
        if ok.size:
            k = ok[0]
            return float(a[k]), float(b[k]), float(c[k])
    return 0.3, 1.0, 0.9  # Grashof; mu from 42.8 to 86.2 deg


def _four_bar_over(cs: np.ndarray, rng):
    """A crank-rocker on O = (0, 0), O2 = (1, 0) over the crank directions `cs` (rows of
    cos, sin): its lengths, the crank pins A and coupler-rocker pins B."""
    a, b, c = crank_rocker(rng)
    crank = a * cs
    rocker_pivot = np.broadcast_to(np.array([1.0, 0.0]), crank.shape)
    pin, _ = _circles(crank, b, rocker_pivot, c, _sign(rng))
    return crank, pin


# ---------------------------------------------------------------- four-bar and dyad

ATTACH = {  # (u range, |v| range) of a dyad's pin on each body of the four-bar, in its length
    "ground": ((-0.5, 1.5), (0.25, 1.0)),
    "crank": ((0.0, 1.0), (0.5, 1.5)),
    "coupler": ((-0.3, 1.3), (0.25, 1.0)),
    "rocker": ((0.2, 1.4), (0.2, 0.8)),
}


def _draw_local(rng, role: str) -> tuple[float, float]:
    (u0, u1), (v0, v1) = ATTACH[role]
    return rng.uniform(u0, u1), _sign(rng) * rng.uniform(v0, v1)


def four_bar_and_dyad(inv, drive: int, rng, keep=()):
    """Places over the turn of a four-bar (ground, crank, coupler, rocker) with a dyad between
    two of its bodies (none for the four-bar itself); None when this draw fails."""
    chain, g, k = inv.chain, inv.ground, drive
    loop = inv.loop_with(k) if chain.links > 4 else frozenset(range(4))
    coupler = next(v for v in chain.neighbours(k) if v in loop and v != g)
    rocker = next(v for v in loop if v not in (g, k, coupler))
    cs = _turned(_unit_circle(SAMPLES), np.broadcast_to(_unit_circle(SAMPLES)[rng.integers(SAMPLES)], (SAMPLES, 2)))
    crank_pin, pin = _four_bar_over(cs, rng)
    origin = np.zeros_like(crank_pin)
    rocker_pivot = np.broadcast_to(np.array([1.0, 0.0]), crank_pin.shape)
    at = {_edge(g, k): origin, _edge(k, coupler): crank_pin, _edge(coupler, rocker): pin,
          _edge(rocker, g): rocker_pivot}
    frames = {g: (origin, rocker_pivot, "ground"), k: (origin, crank_pin, "crank"),
              coupler: (crank_pin, pin, "coupler"), rocker: (rocker_pivot, pin, "rocker")}
    rest = [v for v in range(chain.links) if v not in loop]
    if not rest:
        return at
    x, y = rest
    on_x = next(v for v in chain.neighbours(x) if v in loop)
    on_y = next(v for v in chain.neighbours(y) if v in loop)
    px = _local(frames[on_x][0], frames[on_x][1], *_draw_local(rng, frames[on_x][2]))
    py = _local(frames[on_y][0], frames[on_y][1], *_draw_local(rng, frames[on_y][2]))
    d = np.sqrt(_dot(px - py, px - py))
    lengths = _dyad_lengths(float(d.min()), float(d.max()), rng)
    if lengths is None:
        return None
    joint, ok = _circles(px, lengths[0], py, lengths[1], _sign(rng))
    if not ok.all():  # cannot happen within the bounds: kept as a guard
        return None
    at[_edge(x, on_x)] = px
    at[_edge(y, on_y)] = py
    at[_edge(x, y)] = joint
    return at


# ---------------------------------------------------------------- triads (Stephenson's chain)

def _stephenson_roles(inv, drive: int):
    """Stephenson's chain: (its two ternary links), (the two binary links of its four-bar
    loop), {ternary link: the binary path link pinned to it}."""
    chain = inv.chain
    loop = chain.loops4()[0]
    ternary = sorted(v for v in loop if chain.degree(v) == 3)
    binary = sorted(v for v in loop if chain.degree(v) == 2)
    path = [v for v in range(chain.links) if v not in loop]
    beside = {t: next(p for p in path if chain.adjacent(p, t)) for t in ternary}
    return ternary, binary, beside


def _inner_four_bar(rng):
    """The four-bar loop of a triad in the frame of one ternary link (its pins at (0, 0) and
    (1, 0)), a crank-rocker over GRID angles of its crank qa: qa's far pin A, qb's far pin B,
    and the third pin E of the other ternary link."""
    cs = _unit_circle(GRID)
    a_pin, b_pin = _four_bar_over(cs, rng)
    u, v = rng.uniform(-0.3, 1.3), _sign(rng) * rng.uniform(0.3, 1.0)
    return a_pin, b_pin, _local(a_pin, b_pin, u, v)


def triad_end(inv, drive: int, rng, keep=()):
    """Places over the turn of a Stephenson chain driven at the joint of a ternary link T and
    the path link p, the crank and rod in line with a stretch of E's curve, drawn where the
    closures `keep` are open (module docstring); None when this draw fails."""
    g = inv.ground
    (t1, t2), (qa, qb), beside = _stephenson_roles(inv, drive)
    big = g if g in (t1, t2) else drive
    other = t2 if big == t1 else t1
    p, p2 = beside[big], beside[other]
    a_pin, b_pin, e = _inner_four_bar(rng)
    step = 2.0 * math.pi / GRID
    de, dde = _central(e, step)
    speed = np.sqrt(_dot(de, de))
    radius = speed ** 3 / np.maximum(np.abs(_cross(de, dde)), 1e-300)
    nodes = {_edge(big, qa): _fixed((0.0, 0.0), e), _edge(big, qb): _fixed((1.0, 0.0), e), _edge(qa, other): a_pin,
             _edge(qb, other): b_pin, _edge(other, p2): e, _edge(p, p2): e - de}  # the rod along E's path
    usable = np.flatnonzero((speed > 0.2 * speed.max()) & open_rows(nodes, keep, MU_NODE))
    if usable.size == 0:
        return None
    flat = usable[radius[usable] >= np.quantile(radius[usable], 0.5)]
    j0 = int(flat[rng.integers(flat.size)])
    tangent = de[j0] / speed[j0]
    normal = _perp(tangent)
    ahead, lean = _sign(rng), _sign(rng)
    lam = rng.uniform(2.0, 3.5)
    seg = np.sqrt(_dot(np.roll(e, -1, axis=0) - e, np.roll(e, -1, axis=0) - e))
    for frac in (0.9, 0.7, 0.55, 0.42, 0.32, 0.25):
        r = frac * min(float(radius[j0]), float(seg.sum()) / 8.0)  # E's stroke: within its bend, an eighth of its curve
        length = lam * r
        pivot = e[j0] - ahead * math.sqrt(length * length - r * r) * tangent
        c0 = pivot + lean * r * normal
        crank = pivot + r * _turned((c0 - pivot) / r, _unit_circle(SAMPLES))
        idx = _window(seg, j0, 2.5 * r)  # E's curve within 2.5 r of the drawing, each way
        if idx is None:
            continue
        coarse = e[idx][None, :, :] - crank[::COARSE, None, :]  # a fifth of the rows first: most fail there
        if _window_root(_dot(coarse, coarse) - length * length) is None:
            continue
        diff = e[idx][None, :, :] - crank[:, None, :]
        found = _window_root(_dot(diff, diff) - length * length)
        if found is None:
            continue
        j, w = found
        lo, hi = idx[j], idx[j + 1]
        w = w[:, None]
        at_e, a_at, b_at = (_along(points, lo, hi, w, j0) for points in (e, a_pin, b_pin))
        path = de[lo] + w * (de[hi] - de[lo])
        rod = at_e - crank
        if (np.abs(_dot(rod, path)) / np.sqrt(_dot(rod, rod) * _dot(path, path))).min() < TRIAD_INDEX:
            continue
        at = {_edge(big, qa): _fixed((0.0, 0.0), crank), _edge(big, qb): _fixed((1.0, 0.0), crank),
              _edge(big, p): _fixed(pivot, crank),
              _edge(qa, other): a_at, _edge(qb, other): b_at, _edge(other, p2): at_e, _edge(p, p2): crank}
        if not np.all(open_rows(at, keep, MU_CLOSURE)):
            continue
        if g == p:  # the path link is the ground: the same motion seen from it
            at = _seen_from(at, _edge(big, p), _edge(p, p2))
        return at
    return None


def _window(seg: np.ndarray, j0: int, reach: float):
    """Grid indices (periodic, in order) of a closed curve (its segments' lengths `seg`)
    within arc length `reach` of index j0 each way (one step more); None when that takes in
    nearly the whole curve."""
    n = seg.size
    seg = np.roll(seg, -j0)  # seg[m]: from j0 + m to j0 + m + 1
    ahead = int(np.searchsorted(np.cumsum(seg), reach)) + 1
    back = int(np.searchsorted(np.cumsum(seg[::-1]), reach)) + 1
    if ahead + back + 1 > n - 2:
        return None
    return (j0 + np.arange(-back, ahead + 1)) % n


def _window_root(h: np.ndarray):
    """Per row of h (samples x window), the one sign change's index and fraction; None when a
    row has no change, more than one, or a window end changes sign over the rows."""
    positive = h > 0.0
    if not (positive[:, 0].all() or (~positive[:, 0]).all()) or not (positive[:, -1].all() or (~positive[:, -1]).all()):
        return None
    changes = positive[:, 1:] != positive[:, :-1]
    if not (changes.sum(axis=1) == 1).all():
        return None
    j = np.argmax(changes, axis=1)
    rows = np.arange(h.shape[0])
    h0, h1 = h[rows, j], h[rows, j + 1]
    return j, h0 / (h0 - h1)


def _dyad_lengths(d_min: float, d_max: float, rng):
    """(l1, l2) of a dyad spanning d_min to d_max with its transmission angle within
    [MU_DYAD, 180 - MU_DYAD] (module docstring), or None."""
    if d_min < 0.1 * d_max:
        return None
    rho, cmu = rng.uniform(0.6, 1.6), math.cos(MU_DYAD)
    lo = d_max / math.sqrt(1.0 + rho * rho + 2.0 * rho * cmu)
    hi = d_min / math.sqrt(1.0 + rho * rho - 2.0 * rho * cmu)
    if not lo < 0.98 * hi:
        return None
    l1 = lo * (hi / lo) ** rng.uniform(0.25, 0.75)
    return l1, rho * l1


def _seen_from(at: dict, pivot, pin) -> dict:
    """Every place in the frame of the body through `pivot` and `pin` (two of its joints),
    turned so that row 0 stays as drawn."""
    o = at[pivot]
    arm = at[pin] - o
    arm = arm / np.sqrt(_dot(arm, arm))[:, None]
    turn = np.stack([_dot(arm, arm[0]), _cross(arm, arm[0])], axis=-1)  # arm -> arm[0]
    return {key: o[0] + _turned(place - o, turn) for key, place in at.items()}


def triad_middle(inv, drive: int, rng, keep=()):
    """Places over the turn of a Stephenson chain driven at the joint of its two binary path
    links (module docstring); None when this draw fails."""
    g = inv.ground
    (t1, t2), (qa, qb), beside = _stephenson_roles(inv, drive)
    tg = t1 if beside[t1] == g else t2
    tk = t2 if tg == t1 else t1
    a_pin, b_pin, e = _inner_four_bar(rng)
    o1 = _local(np.zeros(2), np.array([1.0, 0.0]), rng.uniform(-0.5, 1.5), _sign(rng) * rng.uniform(0.3, 1.2))
    rel = e - o1
    rho = np.sqrt(_dot(rel, rel))
    step = 2.0 * math.pi / GRID
    drho, _ = _central(rho, step)
    de, _ = _central(e, step)
    nodes = {_edge(g, tg): _fixed(o1, e), _edge(tg, qa): _fixed((0.0, 0.0), e), _edge(tg, qb): _fixed((1.0, 0.0), e),
             _edge(qa, tk): a_pin, _edge(qb, tk): b_pin, _edge(tk, drive): e}
    good = (np.abs(drho) >= TRIAD_INDEX * np.sqrt(_dot(de, de))) & open_rows(nodes, keep, MU_CLOSURE)
    runs = [r for r in (_longest_run(good & (drho > 0.0), rho), _longest_run(good & (drho < 0.0), rho))
            if r is not None]
    if not runs:
        return None
    run = max(runs, key=lambda r: abs(rho[r[-1]] - rho[r[0]]))  # the first of equal spans
    if run.size < 8:
        return None
    if rho[run[-1]] < rho[run[0]]:
        run = run[::-1]  # rho increasing along it
    if not (np.diff(rho[run]) > 0.0).all():
        return None
    r_lo, r_hi = float(rho[run[0]]), float(rho[run[-1]])
    if r_hi - r_lo < 0.1:
        return None
    mid, radius = 0.5 * (r_lo + r_hi), rng.uniform(0.55, 0.85) * 0.5 * (r_hi - r_lo)
    inside = run[(rho[run] > mid - 0.8 * radius) & (rho[run] < mid + 0.8 * radius)]
    if inside.size == 0:
        return None
    j0 = int(inside[rng.integers(inside.size)])
    beta = rng.uniform(0.0, 2.0 * math.pi)
    centre = np.array([mid * math.cos(beta), mid * math.sin(beta)])
    c0, ok = _circles(np.zeros(2), rho[j0], centre, np.float64(radius), _sign(rng))
    if not ok:
        return None
    pins = _circle_around(centre, c0, SAMPLES)
    dist = np.sqrt(_dot(pins, pins))
    where = np.interp(dist, rho[run], np.arange(run.size, dtype=float))
    lo = np.minimum(np.floor(where).astype(int), run.size - 2)
    w = (where - lo)[:, None]
    a_at, b_at, e_at = (_along(points, run[lo], run[lo + 1], w, j0) for points in (a_pin, b_pin, e))
    rel_at = e_at - o1
    turn = np.stack([_dot(rel_at, pins), _cross(rel_at, pins)], axis=-1) / (
        np.sqrt(_dot(rel_at, rel_at) * _dot(pins, pins)))[:, None]  # rel_at -> the crank pin's direction

    def place(local):
        return _turned(np.broadcast_to(local, rel_at.shape) - o1, turn)
    return {_edge(g, tg): np.zeros_like(pins), _edge(g, drive): np.broadcast_to(centre, pins.shape),
            _edge(tg, qa): place(np.zeros(2)), _edge(tg, qb): place(np.array([1.0, 0.0])),
            _edge(qa, tk): place(a_at), _edge(qb, tk): place(b_at), _edge(tk, drive): place(e_at)}


def _circle_around(centre: np.ndarray, start: np.ndarray, n: int) -> np.ndarray:
    """n points of the circle about `centre` through `start`, from it counter-clockwise."""
    return centre + _turned(np.broadcast_to(start - centre, (n, 2)), _unit_circle(n))


def _longest_run(mask: np.ndarray, rho: np.ndarray):
    """Indices (in order, periodic) of the run of True in `mask` spanning the widest range of
    rho (the first of equal ones); None when there is none (or the whole circle is True: no
    ends)."""
    n = mask.size
    if mask.all() or not mask.any():
        return None
    shift = int(np.flatnonzero(~mask)[0])  # the scan begins at a False
    rolled = np.roll(mask, -shift)
    edges = np.diff(np.concatenate([[False], rolled, [False]]).astype(np.int8))
    starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)  # [start, stop)
    spans = np.abs(rho[(stops - 1 + shift) % n] - rho[(starts + shift) % n])
    k = int(np.argmax(spans))
    return (np.arange(starts[k], stops[k]) + shift) % n


# ---------------------------------------------------------------- the target's points

def add_points(at: dict, chain, target: int, task: str, rng) -> dict:
    """The tracer P (path), the body's frame P, Q (motion) on the target link, placed in the
    frame of its first two pins; nothing for a function's output."""
    if task == "function":
        return at
    pins = sorted(e for e in at if isinstance(e, tuple) and target in e)
    origin, toward = at[pins[0]], at[pins[1]]
    u, v = rng.uniform(-0.2, 1.2), _sign(rng) * rng.uniform(0.25, 0.9)
    at = dict(at)
    at["P"] = _local(origin, toward, u, v)
    if task == "motion":
        at["Q"] = _local(origin, toward, u + 0.5, v)
    return at


def score(at: dict, inv, target: int, task: str) -> float:
    """How well a candidate serves as a start, in [0, 1]: for a path or a body, the diagonal of
    P's path over the diagonal of everything the linkage sweeps (a compact linkage for its
    path); for a function, the output's swing over SWING_FULL (at most 1)."""
    if task == "function":
        pins = sorted(e for e in at if isinstance(e, tuple) and target in e)
        pivot = next(e for e in pins if inv.ground in e)
        arm = at[next(e for e in pins if e != pivot)] - at[pivot]
        ref = arm[0]
        across, along = _cross(ref, arm), _dot(ref, arm)
        size = np.sqrt(_dot(ref, ref) * _dot(arm, arm))
        if (size + along).min() <= 1e-12 * size.max():
            return 1.0  # it turns half a turn or more
        half = across / (size + along)  # tan of half the angle from the drawing: monotone in it
        swing = 2.0 * (math.atan(float(half.max())) - math.atan(float(half.min())))
        return min(swing / SWING_FULL, 1.0)
    return _diagonal(at["P"]) / _diagonal(np.concatenate([np.asarray(p) for p in at.values()]))


def _diagonal(points: np.ndarray) -> float:
    span = points.max(axis=0) - points.min(axis=0)
    return float(np.sqrt(_dot(span, span)))


def sketch(inv, drive: int, target: int, task: str, rng, keep=()) -> dict:
    """Places of every pin (and P, Q) over SAMPLES crank angles, row 0 the drawing: of the
    first CANDIDATES candidates whose closures `keep` (triples of pins, open_rows) stay within
    [MU_CLOSURE, 180 - MU_CLOSURE] on every row, the best scoring (the first that scores GOOD),
    out of at most MAX_ATTEMPTS draws (module docstring)."""
    if inv.chain.links == 4 or inv.loop_with(drive) is not None:
        build = four_bar_and_dyad
    elif inv.chain.name == "stephenson":
        middle = inv.chain.degree(inv.ground) == 2 and inv.chain.degree(drive) == 2
        build = triad_middle if middle else triad_end
    else:
        raise ValueError(f"no starting drawing for {inv.name} driven at link {drive}")
    best, best_score, found = None, -1.0, 0
    for _ in range(MAX_ATTEMPTS):
        at = build(inv, drive, rng, keep)
        if at is None or not np.all(open_rows(at, keep, MU_CLOSURE)):
            continue
        at = add_points(at, inv.chain, target, task, rng)
        value = score(at, inv, target, task)
        if value > best_score:
            best, best_score = at, value
        found += 1
        if value >= GOOD[task] or found == CANDIDATES:
            break
    if best is None:
        raise RuntimeError(f"no starting drawing of {inv.name} driven at link {drive} in {MAX_ATTEMPTS} draws")
    return best


# ---------------------------------------------------------------- placed in the box

def fit(at: dict, task: str, box, rng) -> dict:
    """Row 0 of every place, turned (a multiple of 45 deg whose bounding box's proportions
    best match the box's), scaled and moved so that the tracer's path (a body's origin; the
    whole linkage's swept places for a function) fills the box (x_lo, y_lo, x_hi, y_hi) as far
    as it can, centred in it; coordinates rounded to DIGITS significant digits of the box."""
    x_lo, y_lo, x_hi, y_hi = (float(v) for v in box)
    width, height = x_hi - x_lo, y_hi - y_lo
    if not (all(math.isfinite(v) for v in (x_lo, y_lo, width, height)) and width >= 0.0 and height >= 0.0
            and max(width, height) > 0.0):
        raise ValueError(f"a box (x_lo, y_lo, x_hi, y_hi) of finite coordinates, lo <= hi and a positive size, "
                         f"not {tuple(box)}")
    size = max(width, height)
    width, height = max(width, 0.2 * size), max(height, 0.2 * size)
    shown = at["P"] if task in ("path", "motion") else np.concatenate([np.asarray(p) for p in at.values()])
    first = int(rng.integers(len(ROTATIONS)))
    best = None
    for k in range(len(ROTATIONS)):
        c, s = ROTATIONS[(first + k) % len(ROTATIONS)]
        x = c * shown[:, 0] - s * shown[:, 1]
        y = s * shown[:, 0] + c * shown[:, 1]
        w, h = float(x.max() - x.min()), float(y.max() - y.min())
        floor = 1e-9 * max(w, h)
        miss = abs(math.log(max(w, floor) / max(h, floor)) - math.log(width / height))
        if best is None or miss < best[0] - 1e-9:
            best = (miss, c, s, float(x.min()), float(x.max()), float(y.min()), float(y.max()))
    _, c, s, px_lo, px_hi, py_lo, py_hi = best
    scale = min(width / max(px_hi - px_lo, 1e-300), height / max(py_hi - py_lo, 1e-300))
    cx, cy = 0.5 * (px_lo + px_hi), 0.5 * (py_lo + py_hi)
    tx, ty = 0.5 * (x_lo + x_hi), 0.5 * (y_lo + y_hi)
    digits = DIGITS - math.floor(math.log10(size))
    out = {}
    for key, place in at.items():
        x0, y0 = float(place[0][0]), float(place[0][1])
        x, y = c * x0 - s * y0, s * x0 + c * y0
        out[key] = (round(tx + scale * (x - cx), digits), round(ty + scale * (y - cy), digits))
    return out
