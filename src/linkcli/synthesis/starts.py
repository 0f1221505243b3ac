"""Starting designs of the shared search: the home's draws (Population.starts: the drawing,
draws around it, draws in the boxes), completed by the timing each one fits best.

* Prescribed timing with a free offset: OFFSETS offsets across its range, each one hypothesis
  (the targets' residuals at base + offset); the best is kept.
* Free timing: the traced point's curve (or the followed frame's: origin and angle) over one
  turn on the model's grid; target k put at the drive value q_j + s lam 2 pi c_k (c_k: the
  targets' cumulative chord length, 0 for the first and 1 for the last), for every start
  sample j (every START_STRIDE-th), share of the turn lam (FRACTIONS) and direction s, the
  curve interpolated linearly between its samples; the hypothesis nearest the targets (sum of
  squared distances, plus the angle's, weighted, for a frame) gives q_1 and the increments
  (the four-bar's timing hypotheses, types/path_generation/starts.py, without its similarity
  fit: a drawing's pivots may be fixed).
* Function generation: free start angles drawn uniformly within their bounds.

Every hypothesis counts as one evaluation against the budget.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.synthesis.model import GRID, HUGE, TWO_PI, Model

OFFSETS = 24
START_STRIDE = 3
FRACTIONS = (0.05, 0.12, 0.25, 0.45, 0.7, 0.95)
CHUNK = 1_000_000  # complex elements per block of hypotheses


def hypotheses_per_draw(model: Model) -> int:
    if model.timing == "free":
        return len(range(0, GRID, START_STRIDE)) * len(FRACTIONS) * len(model.directions()) + 1
    if model.timing == "prescribed" and model.free[model.k_home]:
        return OFFSETS + 1
    return 1


def draws(model: Model, rng, count: int):
    """(x (count, nx), s (count,)): the home's draws completed by their best timing."""
    k = model.k_home
    x = np.repeat(((model.lo + model.hi) / 2.0)[None, :], count, axis=0)
    x[:, :k] = model.pop.starts(rng, count)
    dirs = model.directions()
    s = np.full(count, dirs[0])
    if model.timing == "prescribed":
        if model.free[k]:
            x[:, k] = _best_offset(model, x)
        else:
            x[:, k] = model.lo[k]
    elif model.timing == "free":
        x, s = _free_timing(model, x)
    else:
        for j in (k, k + 1):
            if model.free[j]:
                x[:, j] = model.lo[j] + (model.hi[j] - model.lo[j]) * rng.random(count)
    return x, s


def _features(model: Model, motion, cols=slice(None)):
    """(N, S, F) complex features of a motion and the targets' (n, F): the traced point, or the
    frame's origin and its direction (weighted), whose squared distance is the objective."""
    if model.kind == "path":
        p = motion.points[:, cols, 0, :]
        t = model.targets
        return (p[..., 0] + 1j * p[..., 1])[..., None], (t[:, 0] + 1j * t[:, 1])[:, None]
    o = motion.origins[:, cols, 0, :]
    a = motion.angles[:, cols, 0]
    w = model.weight
    t = model.targets
    return (np.stack([o[..., 0] + 1j * o[..., 1], w * np.exp(1j * a)], axis=-1),
            np.stack([t[:, 0] + 1j * t[:, 1], w * np.exp(1j * t[:, 2])], axis=-1))


def _best_offset(model: Model, x: np.ndarray) -> np.ndarray:
    """Each draw's best offset among OFFSETS across its range (module docstring)."""
    k = model.k_home
    offsets = model.lo[k] + (model.hi[k] - model.lo[k]) * (np.arange(OFFSETS) + 0.5) / OFFSETS
    n = model.n
    q = (model.base[None, :] + offsets[:, None]).reshape(-1)  # (H n,)
    out = np.empty(len(x))
    per = max(1, CHUNK // max(1, len(q)))
    for at in range(0, len(x), per):
        xs = x[at:at + per]
        with np.errstate(all="ignore"):
            motion = model.pop.kinematics(xs, np.repeat(q[None, :], len(xs), axis=0))
        f, t = _features(model, motion)
        f = f.reshape(len(xs), OFFSETS, n, -1)
        cost = np.sum(np.abs(f - t[None, None]) ** 2, axis=(2, 3))
        cost = np.where(np.isfinite(cost) & motion.valid.reshape(len(xs), OFFSETS, n).all(axis=2), cost, HUGE)
        out[at:at + per] = offsets[np.argmin(cost, axis=1)]
    model_budget_add(model, len(x) * OFFSETS)
    return out


def _free_timing(model: Model, x: np.ndarray):
    """Each draw's best timing hypothesis on its curve over a turn (module docstring)."""
    k, n = model.k_home, model.n
    grid = np.arange(GRID) * (TWO_PI / GRID)
    with np.errstate(all="ignore"):
        motion = model.pop.kinematics(x, np.repeat(grid[None, :], len(x), axis=0))
    f, t = _features(model, motion)  # (N, G, F), (n, F)
    f = np.where(motion.valid[..., None], f, np.nan)
    pts = model.targets[:, :2]
    chord = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))])
    c = chord / chord[-1] if chord[-1] > 0 else np.linspace(0.0, 1.0, n)
    dirs = np.array(model.directions())
    starts = np.arange(0, GRID, START_STRIDE)
    lam = np.array(FRACTIONS)
    # hypotheses (H,): start sample, share, direction -> drive values (H, n) in grid steps
    j, l, d = (a.reshape(-1) for a in np.meshgrid(starts, lam, dirs, indexing="ij"))
    pos = j[:, None] + d[:, None] * l[:, None] * GRID * c[None, :]
    lo = np.floor(pos).astype(int)
    frac = pos - lo
    i0, i1 = np.mod(lo, GRID), np.mod(lo + 1, GRID)
    best_h = np.empty(len(x), dtype=int)
    per = max(1, CHUNK // max(1, len(j) * n * f.shape[2]))
    for at in range(0, len(x), per):
        fs = f[at:at + per]  # (B, G, F)
        curve = fs[:, i0] * (1 - frac)[None, ..., None] + fs[:, i1] * frac[None, ..., None]  # (B, H, n, F)
        cost = np.sum(np.abs(curve - t[None, None]) ** 2, axis=(2, 3))
        cost = np.where(np.isfinite(cost), cost, HUGE)
        best_h[at:at + per] = np.argmin(cost, axis=1)
    model_budget_add(model, len(x) * len(j))
    q1 = np.mod(j[best_h] * (TWO_PI / GRID), TWO_PI)
    q1 = np.where(q1 > math.pi, q1 - TWO_PI, q1)
    s = d[best_h].astype(float)
    x = x.copy()
    x[:, k] = q1
    x[:, k + 1:] = (l[best_h] * TWO_PI)[:, None] * np.diff(c)[None, :]
    return x, s


def model_budget_add(model: Model, count: int) -> None:
    budget = getattr(model, "budget", None)
    if budget is not None:
        budget.add(count)
