"""Starting candidates for path generation: seeded draws completed in closed form (numpy).

A draw fixes the shape of a linkage (lengths and coupler point inside their bounds, in the
Grashof class asked for), a ground angle, a pivot and a branch. What enters the coupler
point linearly is then solved for instead of drawn:

* Similarity. With the input angles phi_k set, the coupler curve of the drawn shape in its
  local frame, Q_k = a e^{i phi_k} + e^{i theta_k} p, scales with the linkage, so placing
  it is the linear fit T_k ~ g + u Q_k (complex: g the pivot, u = scale * e^{i gamma}),
  solved in closed form (centred Procrustes without the unit-modulus constraint). The
  scale is clipped to the interval that keeps every scaled length and coupler coordinate
  inside its bounds; a fixed pivot or ground angle stays fixed.
* Free timing. Each target k gets an arc-length position on the drawn curve (sampled at
  CURVE_SAMPLES input angles over one turn): starting at sample j, running a fraction
  lam of the curve's length in a direction, target k sits at the fraction c_k of the way
  (c_k: cumulative chord length of the targets, 0 for the first, 1 for the last). Every
  start j, fraction lam and direction is one hypothesis whose cost is the similarity fit
  above; the best one gives the input angles in order within one turn.
* Coupler point and ground pivot. Once the lengths, the input angles and the ground angle
  are set, P_k = G + R(gamma) A_k + R(gamma + theta_k) p is linear in (G, p): a linear
  least squares fit on the free coordinates (`fit_linear`).

Every hypothesis and every completed draw counts as one objective evaluation.
"""

from __future__ import annotations

import numpy as np

from linkcli.mechanisms.four_bar import closure
from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.search import linalg
from linkcli.types.path_generation.model import N_LINK, SHORTEST, Design

EDGE_GAP = 1e-5  # relative: a crank-rocker this close to its edge lies on it (`edge_like`; the search
# holds its designs 1e-7 of the sum of the lengths inside: model.GRASHOF_MARGIN)
CURVE_SAMPLES = 120  # samples of the coupler curve over one turn (free timing)
START_STRIDE = 3  # every 3rd sample is tried as the first target's position
FRACTIONS = (0.05, 0.12, 0.25, 0.45, 0.7, 0.95)  # share of the curve the targets span
OFFSETS = 24  # prescribed timing with a free offset: hypotheses over its range
CHUNK = 2_000_000  # complex elements per vectorized block of hypotheses
CONDITIONED = 1e-9  # n^2 - |sigma|^2 above this share of n^2: the closed-form fit is well posed
BLOCK = 32_768  # curve points per block of prescribed-timing draws (measured: blocks that stay
# in the cache take half the time of the whole batch at once)


def hypotheses_per_draw(design: Design) -> int:
    """Objective evaluations one draw costs (its hypotheses plus its completion)."""
    if design.timing == "free":
        starts = len(range(0, CURVE_SAMPLES, START_STRIDE))
        return starts * len(FRACTIONS) * len(directions(design)) + 1
    return (OFFSETS if design.free[N_LINK] else 1) + 1


def directions(design: Design) -> tuple[int, ...]:
    return {"ccw": (1,), "cw": (-1,)}.get(design.direction, (1, -1))


# ---------------------------------------------------------------- draws

def branch_signs(design: Design, rng, n: int) -> np.ndarray:
    """-1 open, +1 crossed; "either" draws both."""
    if design.branch == "open":
        return -np.ones(n)
    if design.branch == "crossed":
        return np.ones(n)
    return np.where(rng.random(n) < 0.5, -1.0, 1.0)


def sample_lengths(design: Design, rng, n: int, virtual=None):
    """(n, 4) lengths d, a, b, c uniform in their bounds, in the Grashof class asked for
    and, for an input that must turn fully, inside the transmission window over the turn
    (mu at rho = |d - a| and d + a), when the draws allow it: rejection from up to 32 n
    draws, the rest kept as drawn. With `virtual` (see `virtual_scale`), the fixed lengths
    are drawn as part of the shape too: each pool row gets a scale sigma and its fixed
    lengths the values fixed / sigma; returns (lengths, sigma) then."""
    lo, hi = design.lo[:4], design.hi[:4]
    m = n if design.grashof == "any" else 32 * n
    pool = lo + (hi - lo) * rng.random((m, 4))
    sigma = None
    if virtual is not None:
        sigma = virtual(m)
        fixed = [j for j in range(4) if not design.free[j]]
        pool[:, fixed] = design.lo[fixed] / sigma[:, None]
    if design.grashof == "any":
        return pool if virtual is None else (pool, sigma)
    srt = np.sort(pool, axis=1)
    grashof = srt[:, 0] + srt[:, 3] < (srt[:, 1] + srt[:, 2]) * (1 - 1e-6)
    if design.grashof in SHORTEST:
        ok = grashof & (np.argmin(pool, axis=1) == SHORTEST[design.grashof])
    else:
        ok = ~grashof
    if design.window is not None and design.full_turn:
        dd, a, b, c = pool.T
        cos_mu = lambda r: (b * b + c * c - r * r) / (2 * b * c)
        ok &= (cos_mu(np.abs(dd - a)) <= np.cos(design.window[0])) & (cos_mu(dd + a) >= np.cos(design.window[1]))
    order = np.concatenate([np.flatnonzero(ok), np.flatnonzero(~ok)])[:n]
    return pool[order] if virtual is None else (pool[order], sigma[order])


def virtual_scale(design: Design, rng):
    """When fixed lengths or coupler coordinates pin the scale (the closed-form completion
    can then only turn and move a draw), a sampler of the scale sigma that lets them take
    part in the shape: the reference (the longest fixed length, else the largest fixed
    coupler coordinate) is drawn as if it were free, over the range the free lengths span,
    and sigma = its fixed value / its drawn one; the completion scales the draw by sigma,
    which brings every fixed variable back to its value. None when nothing pins the scale,
    or nothing else could scale with it."""
    free_len = [j for j in range(4) if design.free[j]]
    fixed_len = [j for j in range(4) if not design.free[j]]
    fixed_cp = [j for j in (4, 5) if not design.free[j] and design.lo[j] != 0.0]
    if not free_len or not (fixed_len or fixed_cp):
        return None
    top = max(design.hi[j] for j in free_len)
    vlo, vhi = max(min(design.lo[j] for j in free_len), 0.05 * top), top
    ref = max(fixed_len, key=lambda j: design.lo[j]) if fixed_len else max(fixed_cp, key=lambda j: abs(design.lo[j]))
    value = abs(design.lo[ref])
    return lambda m: value / (vlo + (vhi - vlo) * rng.random(m))


def draw(design: Design, rng, n: int):
    """n raw draws (x, sign, s): every variable uniform in its bounds, lengths in class."""
    x = design.wrapped(design.lo + (design.hi - design.lo) * rng.random((n, design.nx)))
    x[:, :4] = sample_lengths(design, rng, n)
    sign = branch_signs(design, rng, n)
    s = np.full(n, float(directions(design)[0]))
    return x, sign, s


def at_edge(design: Design) -> bool:
    """Whether `edge_shapes` serves the design: a crank-rocker asked for, free timing, no
    transmission window (the edge's fold takes mu to 0 or 180 deg), the lengths and the
    coupler point all free."""
    return (design.grashof == "crank-rocker" and design.timing == "free" and design.window is None
            and bool(design.free[:6].all()))


def edge_like(x: np.ndarray) -> bool:
    """Whether the design x (its lengths d, a, b, c first) is of the shapes `edge_shapes`
    draws: a crank within EDGE_GAP (relative) of the crank-rocker's edge s + l = p + q, no
    longer than the largest input the atlas's edge stratum draws (relative to the ground)."""
    from linkcli.atlas.family import EDGE_INPUT
    d, a = float(x[0]), float(x[1])
    lengths = np.sort(np.asarray(x[:4], dtype=float))
    gap = (lengths[1] + lengths[2]) - (lengths[0] + lengths[3])
    return bool(a == lengths[0] and 0.0 <= gap <= EDGE_GAP * (lengths[1] + lengths[2]) and a <= EDGE_INPUT[1] * d)


def edge_shapes(design: Design, rng, x: np.ndarray) -> np.ndarray:
    """x with its lengths and coupler point replaced by small cranks at the crank-rocker's
    edge (linkcli.atlas.family.draw_edge, the atlas's own stratum: the input 0.005 to 0.12 of
    the ground, s + l short of p + q by 1e-6 to 3e-2 of it, the coupler point 0.3 to 30
    inputs from the crank pin), each scaled to the geometric middle of the factors that
    bring it inside the bounds (`scale_interval`); a row no factor brings inside keeps its
    uniform draw. Free timing's optima often lie on that edge, held by the search's Grashof
    margin (closed18_free's best two), where uniform lengths almost never fall."""
    from linkcli.atlas.family import draw_edge
    rows = draw_edge(rng, len(x))
    shape = np.zeros((len(x), 6))
    shape[:, 0] = 1.0
    shape[:, 1:4], shape[:, 4:6] = rows[:, :3], rows[:, 3:5]
    lo, hi = scale_interval(design, shape)
    fits = np.flatnonzero((lo <= hi) & np.isfinite(hi))
    out = x.copy()
    out[fits, :6] = np.clip(shape[fits] * np.sqrt(lo[fits] * hi[fits])[:, None], design.lo[:6], design.hi[:6])
    return out


def scale_interval(design: Design, x: np.ndarray):
    """(lo, hi) of the factor that keeps every scaled length and coupler coordinate of each
    draw inside its bounds (draws lie inside, so 1 is always in the interval). Column by
    column: a row's maximum over six strided columns cost four times the six divisions
    (the atlas's 100,000 shapes, `atlas_starts.allowed`); the same values."""
    lo, hi = design.lo[:6], design.hi[:6]
    low, high = np.full(len(x), -np.inf), np.full(len(x), np.inf)
    with np.errstate(divide="ignore", invalid="ignore"):
        for j in range(6):
            v = np.ascontiguousarray(x[:, j])
            low = np.maximum(low, np.where(v > 0, lo[j] / v, np.where(v < 0, hi[j] / v, -np.inf)))
            high = np.minimum(high, np.where(v > 0, hi[j] / v, np.where(v < 0, lo[j] / v, np.inf)))
    return np.maximum(low, 1e-12), high


# ---------------------------------------------------------------- closed-form fits

def similarity(design: Design, q: np.ndarray, s_lo, s_hi, g0, gamma0):
    """Fit T_k ~ g + u q_k over the last axis of q (complex). s_lo, s_hi, g0 broadcast
    against q[..., 0]. Returns (u, g, cost).

    g free: centred fit, u = sum (T - Tm) conj(q - qm) / sum |q - qm|^2, g = Tm - u qm;
    g fixed (g0 not None): u = sum (T - g0) conj(q) / sum |q|^2. The modulus of u is then
    clipped to [s_lo, s_hi] (the best modulus for a fixed direction: the cost is quadratic
    in it); a fixed ground angle gamma0 sets the direction, u = clip(Re(u e^{-i gamma0}))
    e^{i gamma0}; a bounded one is clipped into its range."""
    t = design.targets[:, 0] + 1j * design.targets[:, 1]
    if g0 is None:
        qm = q.mean(axis=-1, keepdims=True)
        tc, qc = t - t.mean(), q - qm
    else:
        tc, qc = t - g0, q
    den = np.maximum(np.sum((qc * qc.conj()).real, axis=-1), 1e-300)
    u = np.sum(tc * qc.conj(), axis=-1) / den
    if gamma0 is not None:
        e = np.exp(1j * gamma0)
        u = np.clip((u * np.conj(e)).real, s_lo, s_hi) * e
    else:
        mod = np.clip(np.abs(u), s_lo, s_hi)
        ang = np.angle(u)
        glo, ghi = design.lo[8], design.hi[8]
        if ghi - glo < kin.TWO_PI:
            ang = glo + np.clip(np.mod(ang - glo, kin.TWO_PI), 0.0, ghi - glo)
        u = mod * np.exp(1j * ang)
    g = t.mean() - u * qm[..., 0] if g0 is None else np.full(u.shape, g0, dtype=complex)
    res = t - g[..., None] - u[..., None] * q
    return u, g, np.sum((res * res.conj()).real, axis=-1)


def fixed_pivot(design: Design):
    """The ground pivot as a complex number when both coordinates are fixed, else None."""
    return complex(design.lo[6], design.lo[7]) if not design.free[6] and not design.free[7] else None


def fixed_angle(design: Design):
    return None if design.free[8] else float(design.lo[8])


def apply_similarity(design: Design, x, u, g) -> np.ndarray:
    """Scale the lengths and coupler point by |u|, set gamma = arg u and the pivot g."""
    x = x.copy()
    mod = np.abs(u)
    x[:, :6] *= mod[:, None]
    x[:, 8] = np.angle(u) if design.free[8] else design.lo[8]
    if design.free[8] and design.hi[8] - design.lo[8] >= kin.TWO_PI:
        x[:, 8] = design.lo[8] + np.mod(x[:, 8] - design.lo[8], kin.TWO_PI)
    x[:, 6], x[:, 7] = g.real, g.imag
    return design.wrapped(np.clip(x, design.lo, design.hi))


def fit_linear(design: Design, x: np.ndarray, sign: np.ndarray, s: np.ndarray, with_pose: bool = False):
    """Coupler point and ground pivot by linear least squares, the rest held:

        P_k = G + R(gamma) A_k + R(gamma + theta_k) p,   A_k = a e^{i phi_k}

    is linear in (gx, gy, px, py), with columns (1, 0), (0, 1), e^{i(gamma + theta_k)} and
    i e^{i(gamma + theta_k)}: the normal equations are sums over the targets (the two pivot
    columns and the two coupler columns are orthogonal, each of squared norm n). Fixed
    coordinates move to the right-hand side; the free ones are solved within their bounds
    (`bounded_lstsq`). With all four free, in complex numbers p = px + i py, G = gx + i gy,
    sigma = sum e^{i(gamma + theta_k)}: n p + conj(sigma) G = S1, sigma p + n G = S2, solved
    in closed form where that solution lies inside the bounds; so is n p = S1 (the pivot
    fixed) or n G = S2 (the coupler point fixed). With `with_pose`, the
    closure computed on the way is returned too."""
    free = [j for j in (4, 5, 6, 7) if design.free[j]]
    a = x[:, 1:2]
    p, _ = design.frame(x, sign, s)
    if not free:
        return (x, p) if with_pose else x
    cg, sg = np.cos(x[:, 8:9]), np.sin(x[:, 8:9])
    ca, sa = cg * p.ct - sg * p.st, sg * p.ct + cg * p.st  # e^{i(gamma + theta_k)}
    rx = design.targets[None, :, 0] - a * (cg * p.cphi - sg * p.sphi)
    ry = design.targets[None, :, 1] - a * (sg * p.cphi + cg * p.sphi)
    fixed = {4: (ca, sa), 5: (-sa, ca)}
    for j in (4, 5):
        if not design.free[j]:
            rx = rx - fixed[j][0] * x[:, j:j + 1]
            ry = ry - fixed[j][1] * x[:, j:j + 1]
    if not design.free[6]:
        rx = rx - x[:, 6:7]
    if not design.free[7]:
        ry = ry - x[:, 7:8]
    n = float(design.n_targets)
    sigma = ca.sum(axis=1) + 1j * sa.sum(axis=1)
    h = linear_normal(n, sigma)  # normal matrix over (px, py, gx, gy) and right-hand side
    rhs = np.stack([(ca * rx + sa * ry).sum(axis=1), (ca * ry - sa * rx).sum(axis=1),
                    rx.sum(axis=1), ry.sum(axis=1)], axis=1)
    k = [j - 4 for j in free]
    lo, hi = design.lo[free], design.hi[free]
    x = x.copy()
    rest = np.arange(len(x))
    if len(free) == 4:  # all four free: the complex 2 x 2 system in closed form
        s1, s2 = rhs[:, 0] + 1j * rhs[:, 1], rhs[:, 2] + 1j * rhs[:, 3]
        point, pivot, posed = linear_pair(n, sigma, s1, s2)
        sol = np.stack([point.real, point.imag, pivot.real, pivot.imag], axis=1)
        inside = posed & np.all((sol >= lo) & (sol <= hi), axis=1)
        x[:, free] = np.where(inside[:, None], sol, x[:, free])
        rest = np.flatnonzero(~inside)
    elif k in ([0, 1], [2, 3]):  # the coupler point alone, or the pivot alone: n y = S
        sol = rhs[:, k] / n
        inside = np.all((sol >= lo) & (sol <= hi), axis=1)
        x[:, free] = np.where(inside[:, None], sol, x[:, free])
        rest = np.flatnonzero(~inside)
    if len(rest):
        x[np.ix_(rest, free)] = bounded_lstsq(h[rest][:, k][:, :, k], rhs[rest][:, k], lo, hi)
    return (x, p) if with_pose else x


def linear_normal(n: float, sigma: np.ndarray) -> np.ndarray:
    """The normal matrix (N, 4, 4) of the linear columns (px, py, gx, gy) = (w E_k,
    i w E_k, 1, i) over n targets: their real inner products, n on the diagonal and
    sigma = sum w E_k (N,) off it."""
    h = np.zeros((len(sigma), 4, 4))
    h[:, 0, 0] = h[:, 1, 1] = h[:, 2, 2] = h[:, 3, 3] = n
    h[:, 0, 2] = h[:, 2, 0] = h[:, 1, 3] = h[:, 3, 1] = sigma.real
    h[:, 0, 3] = h[:, 3, 0] = sigma.imag
    h[:, 1, 2] = h[:, 2, 1] = -sigma.imag
    return h


def linear_pair(n: float, sigma, s1, s2):
    """The normal equations of `linear_normal` with all four free, in complex numbers:
    n p + conj(sigma) G = s1, sigma p + n G = s2, solved in closed form (arrays
    broadcast): (p, G, well posed: n^2 - |sigma|^2 > CONDITIONED n^2)."""
    det = n * n - (sigma * sigma.conj()).real
    with np.errstate(divide="ignore", invalid="ignore"):
        point = (n * s1 - sigma.conj() * s2) / det
        pivot = (n * s2 - sigma * s1) / det
    return point, pivot, det > CONDITIONED * n * n


def bounded_lstsq(h: np.ndarray, rhs: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """min |M y - r| subject to lo <= y <= hi for every row at once, given the normal
    equations h = M^T M (N, f, f) and rhs = M^T r (N, f).

    Active set that only grows: solve for the variables not yet held, hold the ones that
    leave their bounds at the bound they crossed, solve again (at most f + 1 passes); a
    held variable's part moves to the right-hand side (rhs - h y_held)."""
    n, f = rhs.shape
    h = h + (1e-12 * np.trace(h, axis1=1, axis2=2) + 1e-300)[:, None, None] * np.eye(f)
    held = np.zeros((n, f), dtype=bool)
    value = np.zeros((n, f))
    y = np.zeros((n, f))
    todo = np.arange(n)  # the rows whose held set changed in the last pass (a row's solve
    # depends on its own held set alone: the others would repeat their last solve)
    for _ in range(f + 1):
        h_t, held_t, value_t = h[todo], held[todo], value[todo]
        free = ~held_t
        r = rhs[todo] - np.einsum("nij,nj->ni", h_t, value_t * held_t)
        y_t = np.nan_to_num(linalg.solve_spd(linalg.restricted(h_t, free), np.where(free, r, value_t)))
        y[todo] = y_t
        low, high = free & (y_t < lo), free & (y_t > hi)
        moved = np.any(low | high, axis=1)
        if not moved.any():
            break
        held[todo] = held_t | low | high
        value[todo] = np.where(low, lo, np.where(high, hi, value_t))
        todo = todo[moved]
    return np.clip(np.where(held, value, y), lo, hi)


# ---------------------------------------------------------------- timing hypotheses

def local_curve(x: np.ndarray, sign: np.ndarray, phi: np.ndarray):
    """Coupler point in the local frame (complex) at input angles phi, and validity."""
    dd, a, b, c = (x[:, k:k + 1] for k in range(4))
    p = closure.frame(a, b, c, dd, phi, sign[:, None])
    lx, ly = p.coupler_point(a, x[:, 4:5], x[:, 5:6])
    return lx + 1j * ly, p.valid


def scan_free(design: Design, x, sign, s_lo, s_hi):
    """Best timing hypothesis per draw: (x with timing, scale, angle and pivot set, s, cost).
    See the module docstring; vectorized over draws, starts and targets."""
    n, m = len(x), CURVE_SAMPLES
    grid = np.arange(m) * (kin.TWO_PI / m)
    q, valid = local_curve(x, sign, grid[None, :])  # cos, sin of the grid once
    seg = np.abs(np.roll(q, -1, axis=1) - q)
    seg = np.where(valid & np.roll(valid, -1, axis=1), seg, 0.0)
    arc = np.concatenate([np.zeros((n, 1)), np.cumsum(seg, axis=1)], axis=1)  # (n, m + 1)
    total = arc[:, -1]
    t = design.targets[:, 0] + 1j * design.targets[:, 1]
    chord = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(t)))])
    frac = chord / chord[-1]
    starts = np.arange(0, m, START_STRIDE)
    g0, gamma0 = fixed_pivot(design), fixed_angle(design)
    best = np.full(n, np.inf)
    best_idx = np.zeros((n, design.n_targets), dtype=int)
    best_s = np.ones(n)
    best_u = np.ones(n, dtype=complex)
    best_g = np.zeros(n, dtype=complex)
    rows_per = max(1, CHUNK // (len(starts) * design.n_targets))
    for r0 in range(0, n, rows_per):
        r = slice(r0, min(n, r0 + rows_per))
        nr = r.stop - r.start
        offset = (np.arange(nr) * 4.0 * (float(total[r].max()) + 1.0))[:, None]
        flat = (arc[r] + offset).ravel()
        for sdir in directions(design):
            for lam in FRACTIONS:
                sig = arc[r][:, starts][:, :, None] + sdir * lam * frac * total[r][:, None, None]
                sig = np.mod(sig, np.maximum(total[r], 1e-300)[:, None, None])
                pos = np.searchsorted(flat, (sig + offset[:, :, None]).ravel(), side="right") - 1
                idx = pos.reshape(sig.shape) - (np.arange(nr) * (m + 1))[:, None, None]
                idx = np.clip(idx, 0, m - 1)
                s0 = np.take_along_axis(arc[r], idx.reshape(nr, -1), axis=1).reshape(sig.shape)
                ln = np.take_along_axis(seg[r], idx.reshape(nr, -1), axis=1).reshape(sig.shape)
                idx = np.mod(idx + (sig - s0 > 0.5 * ln), m)
                qq = np.take_along_axis(q[r], idx.reshape(nr, -1), axis=1).reshape(sig.shape)
                ok = np.take_along_axis(valid[r], idx.reshape(nr, -1), axis=1).reshape(sig.shape).all(axis=2)
                u, g, cost = similarity(design, qq, s_lo[r, None], s_hi[r, None], g0, gamma0)
                cost = np.where(ok & (total[r] > 0)[:, None], cost, np.inf)
                j = np.argmin(cost, axis=1)
                cj = cost[np.arange(nr), j]
                better = cj < best[r]
                rows = np.arange(r.start, r.stop)[better]
                best[rows] = cj[better]
                best_idx[rows] = idx[better, j[better]]
                best_s[rows] = sdir
                best_u[rows] = u[better, j[better]]
                best_g[rows] = g[better, j[better]]
    x = x.copy()
    x[:, N_LINK] = grid[best_idx[:, 0]]
    x[:, N_LINK + 1:] = np.mod(best_s[:, None] * np.diff(best_idx, axis=1), m) * (kin.TWO_PI / m)
    return apply_similarity(design, x, best_u, best_g), best_s, best


def scan_prescribed(design: Design, x, sign, s, s_lo, s_hi):
    """Prescribed timing: the similarity fit at the given input angles; with a free offset,
    OFFSETS values across its range are tried and the best kept."""
    g0, gamma0 = fixed_pivot(design), fixed_angle(design)
    if design.free[N_LINK]:
        lo, hi = design.lo[N_LINK], design.hi[N_LINK]
        width = min(hi - lo, kin.TWO_PI)
        offs = lo + width * np.arange(OFFSETS) / (OFFSETS - (0 if width >= kin.TWO_PI else 1))
    else:
        offs = np.array([design.lo[N_LINK]])
    n = len(x)
    phi = (design.base_phi[None, None, :] + offs[None, :, None]).reshape(1, -1)  # (1, H n)
    best_u, best_g = np.ones(n, dtype=complex), np.zeros(n, dtype=complex)
    best, j = np.full(n, np.inf), np.zeros(n, dtype=int)
    rows_per = max(1, BLOCK // phi.shape[1])  # blocks of draws small enough to stay in cache
    for r0 in range(0, n, rows_per):
        r = slice(r0, min(n, r0 + rows_per))
        q, valid = local_curve(x[r], sign[r], phi)
        q = q.reshape(-1, len(offs), design.n_targets)
        valid = valid.reshape(-1, len(offs), design.n_targets).all(axis=2)
        u, g, cost = similarity(design, q, s_lo[r, None], s_hi[r, None], g0, gamma0)
        cost = np.where(valid, cost, np.inf)
        pick = np.argmin(cost, axis=1)
        rows = np.arange(len(pick))
        j[r], best[r], best_u[r], best_g[r] = pick, cost[rows, pick], u[rows, pick], g[rows, pick]
    x = x.copy()
    x[:, N_LINK] = offs[j]
    return apply_similarity(design, x, best_u, best_g), s, best


def starts(design: Design, rng, n: int, edge: bool = False):
    """n completed draws (x, sign, s): drawn, timed and placed, then fit_linear. Fixed
    lengths and coupler coordinates take part in the drawn shape (`virtual_scale`). `edge`
    (where `at_edge`): shapes at the crank-rocker's edge (`edge_shapes`) instead of uniform
    lengths."""
    x, sign, s = draw(design, rng, n)
    if edge and at_edge(design):
        x = edge_shapes(design, rng, x)
    virtual = virtual_scale(design, rng)
    if virtual is not None:
        x[:, :4], sigma = sample_lengths(design, rng, n, virtual)
        fixed_cp = [j for j in (4, 5) if not design.free[j]]
        x[:, fixed_cp] = design.lo[fixed_cp] / sigma[:, None]
    s_lo, s_hi = scale_interval(design, x)
    if design.timing == "free":
        x, s, _ = scan_free(design, x, sign, s_lo, s_hi)
    else:
        x, s, _ = scan_prescribed(design, x, sign, s, s_lo, s_hi)
    return fit_linear(design, x, sign, s), sign, s


def assign_timing(design: Design, x: np.ndarray, sign: np.ndarray):
    """Free timing without the scan (for plain multistart): each target takes its nearest
    curve sample in the draw's own placement; counted from the first target's sample in
    the turning direction, the sample indices are made non-decreasing (targets in order)."""
    n, m = len(x), CURVE_SAMPLES
    grid = np.arange(m) * (kin.TWO_PI / m)
    q, valid = local_curve(x, sign, grid[None, :])  # cos, sin of the grid once
    glob = (x[:, 6:7] + 1j * x[:, 7:8]) + np.exp(1j * x[:, 8:9]) * q
    t = design.targets[:, 0] + 1j * design.targets[:, 1]
    d2 = np.abs(glob[:, None, :] - t[None, :, None]) ** 2
    d2 = np.where(valid[:, None, :], d2, np.inf)
    nearest = np.argmin(d2, axis=2)
    j1 = nearest[:, :1]
    rows = np.arange(n)[:, None]
    best_cost = np.full(n, np.inf)
    best_steps = np.zeros((n, design.n_targets), dtype=int)
    best_s = np.full(n, float(directions(design)[0]))
    for sdir in directions(design):
        steps = np.maximum.accumulate(np.mod(sdir * (nearest - j1), m), axis=1)
        cost = d2[rows, np.arange(design.n_targets)[None, :], np.mod(j1 + sdir * steps, m)].sum(axis=1)
        better = cost < best_cost
        best_cost = np.where(better, cost, best_cost)
        best_steps[better] = steps[better]
        best_s[better] = sdir
    x = x.copy()
    x[:, N_LINK] = grid[j1[:, 0]]
    x[:, N_LINK + 1:] = np.diff(best_steps, axis=1) * (kin.TWO_PI / m)
    return x, best_s


def plain_starts(design: Design, rng, n: int):
    """n draws with only the timing completed (free: `assign_timing`): the naive baseline."""
    x, sign, s = draw(design, rng, n)
    if design.timing == "free":
        x, s = assign_timing(design, x, sign)
    return x, sign, s
