"""Arc descriptors: the shape of a stretch of curve, free of place, size and turn (numpy).

A stretch of curve (a polyline z_0 .. z_S, complex) is resampled at POINTS points evenly
spaced by arc length from its first point to its last, w_j (j = 0 .. POINTS - 1), and
described by the cosine transform of that sequence (DCT-II), harmonics 1 .. HARMONICS:

    X_k = sum_j w_j cos(pi k (2 j + 1) / (2 POINTS)),    k = 1 .. HARMONICS,

normalized to |X| = 1. Harmonic 0 (the centroid) is left out: translation; the norm:
scale; a turn multiplies every X_k by one unit complex number, so two stretches are
compared by |<X, Y>| (1: the same shape up to a similarity), never by their angle; the
start point is the stretch's first point (an atlas curve has a descriptor for each of
several stretches: `ARCS`); the direction: the stretch run backwards has
X_k (-1)^k. A closed curve (a whole loop) is the stretch that ends where it starts.

Descriptors are stored rounded to integers, X * QUANT, QUANT = 1290: a product of two
is at most 1290^2 and ten of them sum to less than 2^24, so that one float32 matrix
product gives every inner product exactly, whatever the BLAS kernel (and so the same
nearest curves on every machine). Every operation here is a basic one (`portable`).
"""

from __future__ import annotations

import numpy as np

from linkcli.atlas import portable

POINTS = 16  # resampled points of a stretch
HARMONICS = 5  # cosine harmonics kept (1 .. 5): 10 numbers a stretch
QUANT = 1290  # descriptors stored as round(X * QUANT): 10 QUANT^2 < 2^24
# Stretches of each atlas curve: (length, count) as a share of the curve's arc length.
# A closed curve: `count` stretches of that length, their starts 1/count apart (turned by
# a per-curve offset); an open one (a rocking input's): `count` stretches from its first
# point to its last, evenly.
LOOP_ARCS = ((1.0, 8), (0.6, 6), (0.35, 6), (0.2, 5))
OPEN_ARCS = ((1.0, 1), (0.6, 3), (0.35, 4), (0.2, 5))
GOLDEN = 0.6180339887498949  # per-curve offset of a loop's starts: frac(i GOLDEN)


def _cosines() -> np.ndarray:
    """(POINTS, HARMONICS) cos(pi k (2 j + 1) / (2 POINTS))."""
    j = np.arange(POINTS)[:, None]
    k = np.arange(1, HARMONICS + 1)[None, :]
    return portable.sincos(portable.PI * k * (2 * j + 1) / (2 * POINTS))[1]


COSINES = _cosines()
REVERSED = np.array([(-1.0) ** k for k in range(1, HARMONICS + 1)])  # X_k of the stretch run backwards


def arc_fractions(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """(N, S + 1) cumulative arc length of polylines (N, S + 1) as a share of each one's
    whole length (0 .. 1; 0 everywhere for a polyline of no length)."""
    seg = portable.norm(np.diff(x, axis=1), np.diff(y, axis=1))
    run = np.concatenate([np.zeros((len(x), 1)), np.cumsum(seg, axis=1)], axis=1)
    total = run[:, -1:]
    return run / np.where(total > 0.0, total, 1.0)


def interpolate(frac: np.ndarray, values: list[np.ndarray], at: np.ndarray) -> list[np.ndarray]:
    """Each of `values` (N, S + 1), linear in the arc fraction `frac` (N, S + 1), at the
    fractions `at` (N, P) (in [0, 1]): all rows at once (one searchsorted over the rows laid
    end to end, each shifted by 2 x its row number)."""
    n, width = frac.shape
    shift = 2.0 * np.arange(n)[:, None]
    flat = (frac + shift).ravel()
    pos = np.searchsorted(flat, (at + shift).ravel(), side="right").reshape(at.shape) - 1
    idx = np.clip(pos - (width * np.arange(n))[:, None], 0, width - 2)
    f0 = np.take_along_axis(frac, idx, axis=1)
    f1 = np.take_along_axis(frac, idx + 1, axis=1)
    span = f1 - f0
    w = np.clip((at - f0) / np.where(span > 0.0, span, 1.0), 0.0, 1.0)
    out = []
    for v in values:
        v0 = np.take_along_axis(v, idx, axis=1)
        out.append(v0 + w * (np.take_along_axis(v, idx + 1, axis=1) - v0))
    return out


def transform(wx: np.ndarray, wy: np.ndarray) -> np.ndarray:
    """(M, 2 HARMONICS) normalized descriptors [Re X_1.., Im X_1..] of resampled stretches
    (M, POINTS); the sums run in a fixed order (one point at a time). A stretch of no
    length gives zeros."""
    re = np.zeros((len(wx), HARMONICS))
    im = np.zeros((len(wx), HARMONICS))
    for j in range(POINTS):
        re += wx[:, j:j + 1] * COSINES[j]
        im += wy[:, j:j + 1] * COSINES[j]
    size = np.zeros(len(wx))
    for k in range(HARMONICS):
        size += re[:, k] * re[:, k] + im[:, k] * im[:, k]
    size = np.sqrt(size)
    scale = np.where(size > 0.0, 1.0 / np.where(size > 0.0, size, 1.0), 0.0)[:, None]
    return np.concatenate([re * scale, im * scale], axis=1)


def quantized(desc: np.ndarray) -> np.ndarray:
    return np.rint(desc * QUANT).astype(np.int16)


def arc_table(closed: bool) -> tuple[np.ndarray, np.ndarray]:
    """(length, index of the start within its count, count) of each stretch of a closed or
    an open curve, in stored order: (lengths (E,), starts as a share before the offset (E,))."""
    arcs = LOOP_ARCS if closed else OPEN_ARCS
    length = np.concatenate([np.full(count, lam) for lam, count in arcs])
    if closed:
        start = np.concatenate([np.arange(count) / count for _, count in arcs])
    else:
        start = np.concatenate([(1.0 - lam) * np.arange(count) / max(count - 1, 1) for lam, count in arcs])
    return length, start


def stretch_starts(curve: np.ndarray, closed: bool) -> tuple[np.ndarray, np.ndarray]:
    """(start, length) (len(curve), E) of every stretch of curves with indices `curve`."""
    length, start = arc_table(closed)
    if closed:
        offset = np.mod(curve.astype(float) * GOLDEN, 1.0)[:, None]
        return np.mod(start[None, :] + offset, 1.0), np.broadcast_to(length, (len(curve), len(length)))
    return np.broadcast_to(start, (len(curve), len(start))), np.broadcast_to(length, (len(curve), len(length)))


def curve_descriptors(x: np.ndarray, y: np.ndarray, curve: np.ndarray, closed: bool) -> np.ndarray:
    """(N E, 2 HARMONICS) int16 descriptors of every stretch of N curves, all closed or all
    open (polylines (N, S + 1), a closed one ending where it starts), curve by curve."""
    frac = arc_fractions(x, y)
    start, length = stretch_starts(curve, closed)
    t = np.arange(POINTS) / (POINTS - 1)
    at = start[:, :, None] + length[:, :, None] * t  # (N, E, POINTS)
    if closed:
        at = np.mod(at, 1.0)
        at = np.where((t == 1.0) & (length[:, :, None] == 1.0), start[:, :, None], at)
    at = np.clip(at, 0.0, 1.0).reshape(len(x), -1)
    wx, wy = interpolate(frac, [x, y], at)
    return quantized(transform(wx.reshape(-1, POINTS), wy.reshape(-1, POINTS)))


def target_descriptors(points: np.ndarray, closed: bool, shifts: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Descriptors (shifts, 2 HARMONICS) of target points (n, 2) as one stretch, unrounded,
    and the share of the stretch's length at each point (n,) (the polyline's arc length:
    chord lengths). Closed: the polyline back to the first point, described from `shifts`
    starts evenly around it (start i at the share i / shifts)."""
    poly = np.concatenate([points, points[:1]]) if closed else points
    frac = arc_fractions(poly[None, :, 0], poly[None, :, 1])
    t = np.arange(POINTS) / (POINTS - 1)
    start = (np.arange(shifts) / shifts)[:, None]
    at = np.mod(start + t[None, :], 1.0) if closed else np.broadcast_to(t, (shifts, POINTS))
    if closed:
        at[:, -1] = start[:, 0]
    rows = np.broadcast_to(frac, (shifts, frac.shape[1]))
    xs, ys = (np.broadcast_to(poly[None, :, k], (shifts, len(poly))) for k in (0, 1))
    wx, wy = interpolate(np.ascontiguousarray(rows), [xs, ys], at)
    return transform(wx, wy), frac[0, :len(points)]
