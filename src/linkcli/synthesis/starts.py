"""Starting designs of the shared search: the home's draws (Population.starts: the drawing,
draws around it, draws in the boxes), completed by the timing and the placement each one fits
best -- the four-bar's closed-form completion (types/path_generation/starts.py), written for
any home whose population can be moved as a whole.

* Placement. Where the whole drawing may move (every joint free: Population.placement_free),
  the traced curve of a draw scales, turns and shifts with it, so that its placement is the
  linear fit T_k ~ g + u C_k (complex: C_k the traced point, or the followed frame's origin,
  at the targets' drive values; u = scale e^{i gamma}), solved in closed form (centred
  Procrustes without the unit-modulus constraint), each hypothesis's cost the fit's residual;
  the chosen fit moves every joint, z -> g + u z, clipped into its box.
* Timing. Prescribed with a free offset: OFFSETS offsets across its range. Free: target k at
  the drive value q_j + s lam 2 pi c_k (c_k: the targets' cumulative chord length, 0 for the
  first and 1 for the last) on the draw's curve over one turn (the model's grid, interpolated
  linearly), for every START_STRIDE-th start sample j, share of the turn lam (FRACTIONS) and
  direction s. Each hypothesis is scored by its placement's residual (or, where the drawing
  cannot move, by its distances to the targets, plus the angle's, weighted, for a frame).
* Function generation: free start angles drawn uniformly within their bounds (the output
  angle does not change with the placement).

Every hypothesis counts as one evaluation against the budget.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.synthesis.model import GRID, HUGE, TWO_PI, Model

OFFSETS = 24
START_STRIDE = 4
FRACTIONS = (0.05, 0.12, 0.25, 0.45, 0.7, 0.95)
CHUNK = 1_000_000  # complex elements per block of hypotheses


def hypotheses_per_draw(model: Model) -> int:
    if model.timing == "free":
        return len(range(0, GRID, START_STRIDE)) * len(FRACTIONS) * len(model.directions()) + 1
    if model.timing == "prescribed" and model.free[model.k_home]:
        return OFFSETS + 1
    return 1


def draws(model: Model, rng, count: int):
    """(x (count, nx), s (count,)): the home's draws completed by their best timing and
    placement."""
    k = model.k_home
    x = np.repeat(((model.lo + model.hi) / 2.0)[None, :], count, axis=0)
    x[:, :k] = model.pop.starts(rng, count)
    s = np.full(count, model.directions()[0])
    if model.timing == "function":
        for j in (k, k + 1):
            if model.free[j]:
                x[:, j] = model.lo[j] + (model.hi[j] - model.lo[j]) * rng.random(count)
        return x, s
    if model.timing == "free":
        return _free_timing(model, x)
    if model.free[k]:
        offsets = model.lo[k] + (model.hi[k] - model.lo[k]) * (np.arange(OFFSETS) + 0.5) / OFFSETS
    else:
        offsets = np.array([model.lo[k]])
    return _prescribed(model, x, offsets), s


def _features(model: Model, motion):
    """(N, S, F) complex features of a motion and the targets' (n, F): the traced point, or the
    frame's origin and its direction (weighted), whose squared distance is the objective."""
    if model.kind == "path":
        p = motion.points[..., 0, :]
        t = model.targets
        return (p[..., 0] + 1j * p[..., 1])[..., None], (t[:, 0] + 1j * t[:, 1])[:, None]
    o = motion.origins[..., 0, :]
    a = motion.angles[..., 0]
    w = model.weight
    t = model.targets
    return (np.stack([o[..., 0] + 1j * o[..., 1], w * np.exp(1j * a)], axis=-1),
            np.stack([t[:, 0] + 1j * t[:, 1], w * np.exp(1j * t[:, 2])], axis=-1))


def _fit(curve, target):
    """The placement fit of curves (..., n, F) to the targets (n, F) on their first feature
    (the traced point, the frame's origin): (cost (...), g (...), u (...)), the cost over every
    feature after the move (a frame's direction turned by arg u)."""
    c, t = curve[..., 0], target[:, 0]
    cm, tm = c.mean(axis=-1, keepdims=True), t.mean()
    dc = c - cm
    with np.errstate(all="ignore"):
        u = np.sum(np.conj(dc) * (t - tm), axis=-1) / np.sum(np.abs(dc) ** 2, axis=-1)
    u = np.where(np.isfinite(u) & (u != 0), u, 1.0)
    g = tm - u * cm[..., 0]
    moved = curve.copy()
    moved[..., 0] = g[..., None] + u[..., None] * c
    if curve.shape[-1] > 1:
        moved[..., 1:] = curve[..., 1:] * (u / np.abs(u))[..., None, None]
    cost = np.sum(np.abs(moved - target) ** 2, axis=(-2, -1))
    return np.where(np.isfinite(cost), cost, HUGE), g, u


def _cost(curve, target):
    cost = np.sum(np.abs(curve - target) ** 2, axis=(-2, -1))
    return np.where(np.isfinite(cost), cost, HUGE)


def _placed(model: Model, x: np.ndarray, g: np.ndarray, u: np.ndarray) -> np.ndarray:
    """The draws moved by z -> g + u z (every joint), clipped into the boxes."""
    k = model.k_home
    out = x.copy()
    z = x[:, 0:k:2] + 1j * x[:, 1:k:2]
    z = g[:, None] + u[:, None] * z
    out[:, 0:k:2], out[:, 1:k:2] = z.real, z.imag
    out[:, :k] = np.clip(out[:, :k], model.lo[:k], model.hi[:k])
    return out


def _prescribed(model: Model, x: np.ndarray, offsets: np.ndarray) -> np.ndarray:
    """Each draw's best offset (among `offsets`) and, where the drawing may move, placement."""
    k, n, h = model.k_home, model.n, len(offsets)
    move = model.pop.placement_free()
    q = (model.base[None, :] + offsets[:, None]).reshape(-1)  # (H n,)
    best = np.zeros(len(x), dtype=int)
    gs, us = np.zeros(len(x), complex), np.ones(len(x), complex)
    per = max(1, CHUNK // max(1, len(q)))
    for at in range(0, len(x), per):
        xs = x[at:at + per]
        with np.errstate(all="ignore"):
            motion = model.pop.kinematics(xs, np.repeat(q[None, :], len(xs), axis=0))
        f, t = _features(model, motion)
        f = np.where(motion.valid[..., None], f, np.nan).reshape(len(xs), h, n, -1)
        if move:
            cost, g, u = _fit(f, t)
        else:
            cost, g, u = _cost(f, t), np.zeros(f.shape[:2], complex), np.ones(f.shape[:2], complex)
        b = np.argmin(cost, axis=1)
        best[at:at + per] = b
        gs[at:at + per], us[at:at + per] = g[np.arange(len(xs)), b], u[np.arange(len(xs)), b]
    _count(model, len(x) * h)
    x = x.copy()
    x[:, k] = offsets[best]
    return _placed(model, x, gs, us) if move else x


def _free_timing(model: Model, x: np.ndarray):
    """Each draw's best timing hypothesis (and placement) on its curve over a turn."""
    k, n = model.k_home, model.n
    move = model.pop.placement_free()
    grid = np.arange(GRID) * (TWO_PI / GRID)
    with np.errstate(all="ignore"):
        motion = model.pop.kinematics(x, np.repeat(grid[None, :], len(x), axis=0))
    f, t = _features(model, motion)  # (N, G, F), (n, F)
    f = np.where(motion.valid[..., None], f, np.nan)
    pts = model.targets[:, :2]
    chord = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))])
    c = chord / chord[-1] if chord[-1] > 0 else np.linspace(0.0, 1.0, n)
    dirs = np.array(model.directions())
    j, l, d = (a.reshape(-1) for a in np.meshgrid(np.arange(0, GRID, START_STRIDE), np.array(FRACTIONS), dirs,
                                                  indexing="ij"))
    pos = j[:, None] + d[:, None] * l[:, None] * GRID * c[None, :]  # (H, n) in grid steps
    lo = np.floor(pos).astype(int)
    frac = pos - lo
    i0, i1 = np.mod(lo, GRID), np.mod(lo + 1, GRID)
    best = np.empty(len(x), dtype=int)
    gs, us = np.zeros(len(x), complex), np.ones(len(x), complex)
    per = max(1, CHUNK // max(1, len(j) * n * f.shape[2]))
    for at in range(0, len(x), per):
        fs = f[at:at + per]
        curve = fs[:, i0] * (1 - frac)[None, ..., None] + fs[:, i1] * frac[None, ..., None]  # (B, H, n, F)
        if move:
            cost, g, u = _fit(curve, t)
        else:
            cost, g, u = _cost(curve, t), np.zeros(curve.shape[:2], complex), np.ones(curve.shape[:2], complex)
        b = np.argmin(cost, axis=1)
        best[at:at + per] = b
        gs[at:at + per], us[at:at + per] = g[np.arange(len(fs)), b], u[np.arange(len(fs)), b]
    _count(model, len(x) * len(j))
    q1 = np.mod(j[best] * (TWO_PI / GRID), TWO_PI)
    q1 = np.where(q1 > math.pi, q1 - TWO_PI, q1)
    x = x.copy()
    x[:, k] = np.clip(q1, model.lo[k], model.hi[k])
    x[:, k + 1:] = (l[best] * TWO_PI)[:, None] * np.diff(c)[None, :]
    return (_placed(model, x, gs, us) if move else x), d[best].astype(float)


def _count(model: Model, count: int) -> None:
    budget = getattr(model, "budget", None)
    if budget is not None:
        budget.add(count)
