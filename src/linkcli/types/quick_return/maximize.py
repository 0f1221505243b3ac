"""Global maximum of a max-min objective of one variable on an interval (numpy only).

The objective is W(x) = min_k F_k(x) of smooth branches F_k (transmission margins), restricted
to where feasible(x) holds (bounds, link ratio). Method:
1. a dense vectorized scan of n interior points of (lo, hi);
2. feasible runs of the scan; where a run meets an infeasible scan point its boundary is
   located by bisection on feasible() to the last bit (a constrained maximum can sit there);
3. every local maximum of the scanned W (a point not below its neighbours) is refined in the
   bracket of its two neighbours by bisection on the sign of W' (the central difference of the
   active branch, the smallest F_k): the sign changes from + to - exactly at a smooth maximum
   or at the crossing of two branches (a kink), so both are found to ~1e-13 relative, far
   below the printed 6 digits; if the bracket's slopes do not bracket a maximum, golden-section
   search on W settles it.
Why global: between two scan points W can hide a maximum only if it has two extrema within one
spacing (hi - lo) / n. The branches here are trigonometric functions of one angle with a few
extrema over the whole interval, and n = 4096 makes the spacing far smaller than their
separation (the tests check the result against independent dense grids). The best refined
candidate wins; ties (equal within 1e-13) go to the smaller x.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

SCAN_POINTS = 4096
GOLDEN = 0.5 * (np.sqrt(5.0) - 1.0)


@dataclass(frozen=True)
class Optimum:
    x: float          # the maximizer (scan variable)
    value: float      # W(x)
    limited: bool     # True when x is on a constraint boundary (bounds or link ratio)


def _objective(parts: Callable, x) -> np.ndarray:
    return np.min(parts(np.atleast_1d(np.asarray(x, dtype=float))), axis=0)


def _bisect_boundary(feasible: Callable, bad: float, good: float) -> float:
    """The feasible end of the boundary between an infeasible and a feasible point."""
    for _ in range(200):
        mid = 0.5 * (bad + good)
        if mid in (bad, good):
            break
        if bool(feasible(np.array([mid]))[0]):
            good = mid
        else:
            bad = mid
    return good


def _slope_sign(parts: Callable, x: float, step: float, lo: float, hi: float) -> float:
    """Sign of the derivative of the active (smallest) branch at x (central difference)."""
    left, right = max(x - step, lo), min(x + step, hi)
    f = parts(np.array([left, x, right]))
    k = int(np.argmin(f[:, 1]))
    return float(np.sign(f[k, 2] - f[k, 0]))


def _golden(parts: Callable, a: float, b: float) -> float:
    c, d = b - GOLDEN * (b - a), a + GOLDEN * (b - a)
    fc, fd = _objective(parts, c)[0], _objective(parts, d)[0]
    for _ in range(200):
        if b - a <= 4e-16 * max(abs(a), abs(b), 1e-300):
            break
        if fc >= fd:
            b, d, fd = d, c, fc
            c = b - GOLDEN * (b - a)
            fc = _objective(parts, c)[0]
        else:
            a, c, fc = c, d, fd
            d = a + GOLDEN * (b - a)
            fd = _objective(parts, d)[0]
    return c if fc >= fd else d


def _refine(parts: Callable, a: float, b: float, step: float, lo: float, hi: float) -> float:
    """The maximizer of a unimodal W in [a, b]."""
    if _slope_sign(parts, a, step, lo, hi) > 0 > _slope_sign(parts, b, step, lo, hi):
        for _ in range(200):
            mid = 0.5 * (a + b)
            if mid in (a, b):
                break
            if _slope_sign(parts, mid, step, lo, hi) > 0:
                a = mid
            else:
                b = mid
        wa, wb = _objective(parts, np.array([a, b]))
        return a if wa >= wb else b
    return _golden(parts, a, b)


def _runs(x, ok, lo, hi, feasible):
    """(i0, i1, left, right) per run of feasible scan points x[i0..i1]; left/right are the
    bisected boundaries with the infeasible neighbours, or lo/hi at the interval's ends."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], ok.astype(np.int8), [0]))))
    for i0, i1 in zip(edges[0::2], edges[1::2] - 1):
        left = _bisect_boundary(feasible, x[i0 - 1], x[i0]) if i0 > 0 else lo
        right = _bisect_boundary(feasible, x[i1 + 1], x[i1]) if i1 < len(x) - 1 else hi
        yield int(i0), int(i1), float(left), float(right)


def feasible_runs(lo: float, hi: float, feasible: Callable,
                  n: int = SCAN_POINTS) -> list[tuple[float, float]]:
    """The feasible sub-intervals of (lo, hi) seen by the scan, ends bisected."""
    x = lo + (hi - lo) * np.arange(1, n) / n
    ok = np.asarray(feasible(x), dtype=bool)
    return [(left, right) for _, _, left, right in _runs(x, ok, lo, hi, feasible)]


def maximize_min(parts: Callable, lo: float, hi: float, feasible: Callable,
                 n: int = SCAN_POINTS) -> Optimum | None:
    """The global maximum of min_k parts(x)[k] over feasible x in the open interval (lo, hi);
    None when no scan point is feasible. `parts(x)` maps an array (m,) to (K, m);
    `feasible(x)` to a bool array (m,)."""
    x = lo + (hi - lo) * np.arange(1, n) / n
    w = _objective(parts, x)
    ok = np.asarray(feasible(x), dtype=bool) & np.isfinite(w)
    if not ok.any():
        return None
    step = 1e-5 * (hi - lo)
    cands: list[tuple[float, float, bool]] = []
    for i0, i1, left, right in _runs(x, ok, lo, hi, feasible):
        for end, limited in ((left, i0 > 0), (right, i1 < len(x) - 1)):
            if limited:
                cands.append((float(_objective(parts, end)[0]), end, True))
        run = w[i0:i1 + 1]
        up = np.concatenate(([True], run[1:] >= run[:-1]))
        down = np.concatenate((run[:-1] >= run[1:], [True]))
        for j in np.flatnonzero(up & down):
            i = i0 + j
            a = x[i - 1] if i > i0 else left
            b = x[i + 1] if i < i1 else right
            best = _refine(parts, float(a), float(b), step, lo, hi)
            limited = False
            for end, is_bound in ((left, i0 > 0), (right, i1 < len(x) - 1)):
                if is_bound and abs(best - end) <= 1e-9 * (hi - lo):
                    best, limited = end, True  # converged onto the constraint boundary
            cands.append((float(_objective(parts, best)[0]), best, limited))
    top = max(v for v, _, _ in cands)
    value, where, limited = min((c for c in cands if c[0] >= top - 1e-13 * max(1.0, abs(top))),
                                key=lambda c: c[1])
    return Optimum(float(where), float(value), bool(limited))
