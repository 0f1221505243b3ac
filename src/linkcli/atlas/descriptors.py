"""Arc descriptors: the shape of a stretch of curve, free of place, size and turn (numpy).

A stretch of curve (a polyline z_0 .. z_S, complex) is resampled at POINTS points evenly
spaced by arc length from its first point to its last, w_j (j = 0 .. POINTS - 1), and
described by the cosine transform of that sequence (DCT-II), harmonics 1 .. HARMONICS:

    X_k = sum_j w_j cos(pi k (2 j + 1) / (2 POINTS)),    k = 1 .. HARMONICS,

normalized to |X| = 1. Harmonic 0 (the centroid) is left out: translation; the norm:
scale; a turn multiplies every X_k by one unit complex number, so two stretches are
compared by |<X, Y>| (1: the same shape up to a similarity), never by their angle; the
start point is the stretch's first point (an atlas curve has a descriptor for each of
several stretches: `LOOP_ARCS`, `OPEN_ARCS`); the direction: the stretch run backwards has
X_k (-1)^k.

A whole loop (a closed curve, or targets that close on themselves) has no first point:
its ring descriptor is free of the start as well. The loop is resampled at RING_POINTS
points evenly spaced by arc length, w_j, and described by its Fourier coefficients

    c_k = sum_j w_j e^{-2 pi i k j / RING_POINTS},    k = +-1 .. +-RING_HARMONICS,

normalized to |c| = 1 (c_0, the centroid, left out). A turn multiplies every c_k by one
unit number, a start moved by a share s of the length by e^{2 pi i k s}, the loop run
backwards swaps c_k and c_-k; so |c_k| are free of start and turn (a prefilter, and a
bound: |sum_k c_k conj(d_k) e^{2 pi i k s}| <= sum_k |c_k| |d_k|), and two loops compare
by the best over the shifts s (`ring_match`). By Parseval, 1 - that best is half the least
mean squared distance between the two resampled loops under a similarity and a start:
the measure the path search's objective is, with arc length for timing. Ring
descriptors are stored as round(c * RING_QUANT) (int16); the match runs elementwise in
float64 with the sums in a fixed order (IEEE-rounded alike on every CPU).

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
LOOP_ARCS = ((0.6, 6), (0.35, 6), (0.2, 5))  # a whole loop: its ring descriptor
OPEN_ARCS = ((1.0, 1), (0.6, 3), (0.35, 4), (0.2, 5))
GOLDEN = 0.6180339887498949  # per-curve offset of a loop's starts: frac(i GOLDEN)
RING_POINTS = 64  # resampled points of a whole loop
RING_HARMONICS = 8  # Fourier orders +-1 .. +-8 kept: 32 numbers a loop
RING_QUANT = 16384  # ring descriptors stored as round(c * RING_QUANT), |c_k| <= 1
RING_ORDERS = np.concatenate([np.arange(1, RING_HARMONICS + 1), -np.arange(1, RING_HARMONICS + 1)])
RING_SWAP = np.concatenate([np.arange(RING_HARMONICS, 2 * RING_HARMONICS), np.arange(RING_HARMONICS)])
RING_SHIFTS = 64  # the match's grid of start shifts (then a parabola through the best three)


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


def interpolate(frac: np.ndarray, values: list[np.ndarray], at: np.ndarray,
                rows: np.ndarray | None = None) -> list[np.ndarray]:
    """Each of `values` (N, S + 1), linear in the arc fraction `frac` (N, S + 1), at the
    fractions `at` (M, P) (in [0, 1]) of row `rows[m]` (M,) (default: row m, M = N): all at
    once (one searchsorted over the rows laid end to end, each shifted by 2 x its row number)."""
    n, width = frac.shape
    rows = np.arange(n) if rows is None else np.asarray(rows, dtype=np.int64)
    flat = (frac + 2.0 * np.arange(n)[:, None]).ravel()
    pos = np.searchsorted(flat, (at + 2.0 * rows[:, None]).ravel(), side="right").reshape(at.shape) - 1
    idx = np.clip(pos - (width * rows)[:, None], 0, width - 2)
    line = rows[:, None]
    f0 = frac[line, idx]
    f1 = frac[line, idx + 1]
    span = f1 - f0
    w = np.clip((at - f0) / np.where(span > 0.0, span, 1.0), 0.0, 1.0)
    out = []
    for v in values:
        v0 = v[line, idx]
        out.append(v0 + w * (v[line, idx + 1] - v0))
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
    return _unit(re, im)


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


def _ring_twiddles(points: int, orders: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(cos, sin) (points, len(orders)) of 2 pi k j / points, the product k j reduced
    modulo `points` first (exact integers: small arguments, the same bits everywhere)."""
    j = np.arange(points)[:, None]
    turn = np.mod(j * orders[None, :], points)
    sin, cos = portable.sincos(2.0 * portable.PI * turn / points)
    return cos, sin


RING_COS, RING_SIN = _ring_twiddles(RING_POINTS, RING_ORDERS)


def ring_transform(wx: np.ndarray, wy: np.ndarray) -> np.ndarray:
    """(M, 4 RING_HARMONICS) normalized ring descriptors [Re c_k.., Im c_k..] (k in
    RING_ORDERS) of loops resampled at RING_POINTS points (M, RING_POINTS); sums in a
    fixed order. A loop of no size gives zeros."""
    m = RING_ORDERS.size
    re = np.zeros((len(wx), m))
    im = np.zeros((len(wx), m))
    for j in range(RING_POINTS):
        x, y = wx[:, j:j + 1], wy[:, j:j + 1]
        re += x * RING_COS[j] + y * RING_SIN[j]
        im += y * RING_COS[j] - x * RING_SIN[j]
    return _unit(re, im)


def ring_descriptors(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """(N, 4 RING_HARMONICS) int16 ring descriptors of N closed curves (polylines (N, S + 1)
    ending where they start), their loops resampled from their first sample."""
    frac = arc_fractions(x, y)
    at = np.broadcast_to(np.arange(RING_POINTS) / RING_POINTS, (len(x), RING_POINTS))
    wx, wy = interpolate(frac, [x, y], np.ascontiguousarray(at))
    return np.rint(ring_transform(wx, wy) * RING_QUANT).astype(np.int16)


def target_ring(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The ring descriptor (4 RING_HARMONICS,) of target points (n, 2) closed back to the
    first (unrounded), and each point's share of the loop's length from the first (n,)
    (chord lengths as arc length)."""
    poly = np.concatenate([points, points[:1]])
    frac = arc_fractions(poly[None, :, 0], poly[None, :, 1])
    at = (np.arange(RING_POINTS) / RING_POINTS)[None, :]
    wx, wy = interpolate(frac, [poly[None, :, 0], poly[None, :, 1]], at)
    return ring_transform(wx, wy)[0], frac[0, :len(points)]


def ring_parts(table: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(Re, Im) (N, 2 RING_HARMONICS) of ring descriptors (N, 4 RING_HARMONICS)."""
    m = RING_ORDERS.size
    return table[:, :m], table[:, m:]


def ring_bound(mags: np.ndarray, query: np.ndarray) -> np.ndarray:
    """(N,) sum_k |c_k| |d_k| of rows with magnitudes `mags` (N, 2 K) and a query
    descriptor (4 K,): at least every shift's |<c, d>| (the triangle inequality)."""
    qre, qim = ring_parts(query[None, :])
    qmag = np.sqrt(qre[0] * qre[0] + qim[0] * qim[0])
    out = np.zeros(len(mags))
    for k in range(RING_ORDERS.size):
        out += mags[:, k] * qmag[k]
    return out


def _shift_matrix() -> np.ndarray:
    """(4 K, 2 RING_SHIFTS) integers round(2^14 e^{2 pi i k m / RING_SHIFTS}) arranged so that
    [Re p, Im p] (N, 4 K) times it is [Re, Im] of sum_k p_k e^{2 pi i k m / M} (N, 2 M)
    scaled by 2^14: with p_k integers below 2^30, every product is below 2^44 and the sums
    of 32 below 2^49, exact in float64 in any order (any BLAS kernel)."""
    cos, sin = (np.rint(t * SHIFT_QUANT) for t in _ring_twiddles(RING_SHIFTS, RING_ORDERS))  # (M, 2 K)
    return np.block([[cos.T, sin.T], [-sin.T, cos.T]])


SHIFT_QUANT = 1 << 14
SHIFT_MATRIX = _shift_matrix()


def ring_match(rows: np.ndarray, query: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(best |sum_k c_k conj(d_k) e^{2 pi i k s}| ^2 over the shifts s (N,), that s (N,), a
    share of the loop in [0, 1)) of ring descriptors `rows` (N, 4 K) and a query (4 K,),
    both integers (stored and quantized descriptors): the query's point at share t lies at
    the row's share t + s. On the grid of RING_SHIFTS shifts (one exact float64 product,
    SHIFT_MATRIX, its twiddles rounded: it only chooses), then evaluated exactly at that
    shift and at the vertex of the parabola through it and its two neighbours, the better
    kept (elementwise, sums in a fixed order; the first best on ties). The same bits on
    every CPU."""
    cre, cim = ring_parts(rows)
    qre, qim = ring_parts(query[None, :])
    pre = cre * qre + cim * qim  # c_k conj(d_k): integers below 2^30
    pim = cim * qre - cre * qim
    sums = np.concatenate([pre, pim], axis=1) @ SHIFT_MATRIX
    sre, sim = sums[:, :RING_SHIFTS], sums[:, RING_SHIFTS:]
    power = (sre * sre + sim * sim) * (1.0 / SHIFT_QUANT ** 2)
    best = np.argmax(power, axis=1)
    n = np.arange(len(rows))
    mid = power[n, best]
    lo, hi = power[n, (best - 1) % RING_SHIFTS], power[n, (best + 1) % RING_SHIFTS]
    curv = lo - 2.0 * mid + hi
    step = np.where(curv < 0.0, 0.5 * (lo - hi) / np.where(curv < 0.0, curv, -1.0), 0.0)
    shift = np.mod((best + np.clip(step, -0.5, 0.5)) / RING_SHIFTS, 1.0)
    on_grid, refined = _ring_at(pre, pim, best / RING_SHIFTS), _ring_at(pre, pim, shift)
    better = refined > on_grid
    return np.where(better, refined, on_grid), np.where(better, shift, best / RING_SHIFTS)


def _ring_at(pre: np.ndarray, pim: np.ndarray, shift: np.ndarray) -> np.ndarray:
    """|sum_k p_k e^{2 pi i k s_n}|^2 (N,) of products p_k = (pre, pim) (N, 2 K), each row
    at its own shift s_n (`portable` twiddles, elementwise, the sums in a fixed order)."""
    sin, cos = portable.sincos(2.0 * portable.PI * np.mod(RING_ORDERS[:, None] * shift[None, :], 1.0))
    sre, sim = np.zeros(len(pre)), np.zeros(len(pre))
    for k in range(RING_ORDERS.size):
        sre += pre[:, k] * cos[k] - pim[:, k] * sin[k]
        sim += pim[:, k] * cos[k] + pre[:, k] * sin[k]
    return sre * sre + sim * sim


def _unit(re: np.ndarray, im: np.ndarray) -> np.ndarray:
    """[re, im] (N, 2 K) of N coefficient rows scaled to unit norm (a zero row stays 0), the
    squares summed harmonic by harmonic in order: basic operations, the same bits on every CPU."""
    size = np.zeros(len(re))
    for k in range(re.shape[1]):
        size += re[:, k] * re[:, k] + im[:, k] * im[:, k]
    size = np.sqrt(size)
    scale = np.where(size > 0.0, 1.0 / np.where(size > 0.0, size, 1.0), 0.0)[:, None]
    return np.concatenate([re * scale, im * scale], axis=1)
