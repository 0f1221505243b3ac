"""The atlas's arithmetic and descriptors, against independent references: numpy's and
math's functions, the Grashof rules of kinematics, an independent loop closure written here
with complex numbers, and invariance of the descriptors under what they must ignore."""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkcli.atlas import descriptors, family, portable
from linkcli.mechanisms.four_bar import kinematics as kin


def test_portable_functions_match_numpy():
    x = np.linspace(-60.0, 60.0, 200_001)
    s, c = portable.sincos(x)
    np.testing.assert_allclose(s, np.sin(x), rtol=0, atol=4e-16)
    np.testing.assert_allclose(c, np.cos(x), rtol=0, atol=4e-16)
    y = np.random.default_rng(1).normal(size=(2, 50_000)) * np.array([[1.0], [1e-3]])
    np.testing.assert_allclose(portable.atan2(y[0], y[1]), np.arctan2(y[0], y[1]), rtol=0, atol=2e-15)
    for yy, xx in ((0.0, 0.0), (0.0, -1.0), (1.0, 0.0), (-1.0, 0.0), (-0.0, -1.0)):
        assert portable.atan2(yy, xx) == pytest.approx(math.atan2(yy, xx), abs=1e-15)
    c = np.linspace(-1.0, 1.0, 10_001)
    np.testing.assert_allclose(portable.acos(c), np.arccos(c), rtol=0, atol=2e-15)


def test_classes_are_the_grashof_classes_of_kinematics():
    linkages = family.draw(2000, 3)
    shares = list(family.CLASS_SHARES)
    shares[0] += family.EDGE_SHARE  # the small cranks at the edge are crank-rockers too
    assert np.bincount(linkages.kind, minlength=5).tolist() == [int(round(share * 2000)) for share in shares]
    for (a, b, c), k in zip(linkages.lengths[::7], linkages.kind[::7]):
        assert kin.GRASHOF_CLASSES[int(kin.grashof_code(a, b, c, 1.0))] == family.CLASSES[k]
        assert kin.input_arcs(a, b, c, 1.0) != []  # every four-bar assembles somewhere


def _closure(d, a, b, c, px, py, sign, phi):
    """Coupler point (complex) by the conventions of docs/format.md, written independently:
    psi = arg(A - B0) -/+ alpha (open / crossed), B = B0 + c e^{i psi}, P = A + p e^{i arg(B - A)}."""
    A = a * np.exp(1j * phi)
    v = A - d
    alpha = np.arccos(np.clip((abs(v) ** 2 + c * c - b * b) / (2 * abs(v) * c), -1, 1))
    B = d + c * np.exp(1j * (np.angle(v) + sign * alpha))
    return A + complex(px, py) * np.exp(1j * np.angle(B - A))


def test_curves_follow_the_loop_closure():
    linkages = family.draw(1000, 7)
    rows = np.arange(0, 1000, 37)
    part = linkages.take(rows)
    phi = family.input_angles(part)
    x, y = family.coupler_points(part, phi)
    for i in range(len(rows)):
        (a, b, c), (px, py), sign = part.lengths[i], part.point[i], part.sign[i]
        p = _closure(1.0, a, b, c, px, py, sign, phi[i, 1:-1])  # the dead points themselves are round-off
        np.testing.assert_allclose(x[i, 1:-1] + 1j * y[i, 1:-1], p, rtol=0, atol=1e-9)
        if part.closed[i]:
            assert phi[i, -1] - phi[i, 0] == pytest.approx(2 * math.pi)
        else:  # a rocking input runs between its two dead points, as kinematics says
            arcs = kin.input_arcs(a, b, c, 1.0)
            assert any(abs(phi[i, 0] - lo) < 1e-9 and abs(phi[i, -1] - hi) < 1e-9 or
                       abs(phi[i, 0] - lo) < 1e-9 and abs(phi[i, -1] - (hi + 2 * math.pi)) < 1e-9
                       for lo, hi in arcs), (arcs, phi[i, 0], phi[i, -1])


def _random_curve(rng, n=400):
    """A smooth closed curve (random Fourier series), sampled evenly in its parameter."""
    t = np.arange(n) / n * 2 * np.pi
    k = np.arange(-4, 5)
    coef = (rng.normal(size=9) + 1j * rng.normal(size=9)) / (1 + np.abs(k)) ** 1.5
    z = (coef[None, :] * np.exp(1j * k[None, :] * t[:, None])).sum(axis=1)
    return np.stack([z.real, z.imag], axis=1)


def _even(pts, n):
    """n points of a closed polyline evenly spaced by arc length (from a dense resampling)."""
    ring = np.concatenate([pts, pts[:1]])
    seg = np.hypot(*np.diff(ring, axis=0).T)
    run = np.concatenate([[0.0], np.cumsum(seg)])
    at = np.arange(n) / n * run[-1]
    return np.stack([np.interp(at, run, ring[:, 0]), np.interp(at, run, ring[:, 1])], axis=1)


def _similarity(u, v):
    u = u[:descriptors.HARMONICS] + 1j * u[descriptors.HARMONICS:]
    v = v[:descriptors.HARMONICS] + 1j * v[descriptors.HARMONICS:]
    return abs(np.vdot(u, v)) / (np.linalg.norm(u) * np.linalg.norm(v))


@pytest.mark.parametrize("seed", range(8))
def test_descriptors_ignore_place_size_turn_start_and_direction(seed):
    rng = np.random.default_rng(seed)
    pts = _random_curve(rng, 4000)
    ref, _ = descriptors.target_descriptors(pts[:1500], closed=False)
    z = (pts[:, 0] + 1j * pts[:, 1]) * rng.uniform(0.01, 100) * np.exp(1j * rng.uniform(-4, 4))
    z = z + complex(*rng.normal(size=2) * 50)
    moved = np.stack([z.real, z.imag], axis=1)
    same, _ = descriptors.target_descriptors(moved[:1500], closed=False)
    assert _similarity(ref[0], same[0]) == pytest.approx(1.0, abs=1e-12)  # place, size, turn
    back, _ = descriptors.target_descriptors(moved[:1500][::-1], closed=False)
    rev = back[0].copy()
    rev[:descriptors.HARMONICS] *= descriptors.REVERSED
    rev[descriptors.HARMONICS:] *= descriptors.REVERSED
    assert _similarity(ref[0], rev) == pytest.approx(1.0, abs=1e-12)  # direction
    # a closed curve started a quarter of its length further: its first stretch is the
    # original's second (points even in arc length, so that sample 100 of 400 is at 1/4)
    even = _even(moved, 400)
    loop, _ = descriptors.target_descriptors(even, closed=True, shifts=4)
    restarted, _ = descriptors.target_descriptors(np.roll(even, -100, axis=0), closed=True, shifts=4)
    assert _similarity(restarted[0], loop[1]) == pytest.approx(1.0, abs=1e-4)
    assert _similarity(ref[0], descriptors.target_descriptors(_random_curve(rng)[:150], False)[0][0]) < 0.999


def test_quantized_inner_products_are_exact_in_float32():
    rng = np.random.default_rng(0)
    big = rng.choice([-descriptors.QUANT, descriptors.QUANT], size=(2000, 2 * descriptors.HARMONICS))
    q = rng.choice([-descriptors.QUANT, descriptors.QUANT], size=(2 * descriptors.HARMONICS, 3))
    exact = big.astype(np.int64) @ q.astype(np.int64)
    assert np.abs(exact).max() < 2 ** 24
    assert np.array_equal((big.astype(np.float32) @ q.astype(np.float32)).astype(np.int64), exact)


def _swap(query):
    """A ring descriptor of the loop run backwards: c_k and c_-k swapped."""
    m = descriptors.RING_ORDERS.size
    return np.concatenate([query[:m][descriptors.RING_SWAP], query[m:][descriptors.RING_SWAP]])


def _arc_share(curve, point):
    """The share of a dense closed polyline's length from its first point to its point
    nearest `point` (independent of linkcli's resampling)."""
    ring = np.concatenate([curve, curve[:1]])
    run = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(ring)))])
    return run[int(np.argmin(np.abs(curve - point)))] / run[-1]


@pytest.mark.parametrize("seed", range(6))
def test_ring_match_is_free_of_start_direction_turn_and_size(seed):
    """A loop given from any start, either way round, turned, scaled and moved matches its
    own ring descriptor to 1 - 1e-5, at the shift where its first point lies on the loop;
    the cosine descriptor of a stretch (the old whole-loop one, eight stored starts) does not."""
    rng = np.random.default_rng([7, seed])
    pts = _random_curve(rng, 4000)
    z = pts[:, 0] + 1j * pts[:, 1]
    x, y = np.append(z.real, z.real[0])[None, :], np.append(z.imag, z.imag[0])[None, :]
    stored = descriptors.ring_descriptors(x, y).astype(float)
    start = int(rng.integers(0, 4000))
    backwards = bool(seed % 2)
    given = np.roll(z, -start) * rng.uniform(0.01, 100) * np.exp(1j * rng.uniform(-4, 4)) + complex(*rng.normal(size=2))
    if backwards:
        given = given[::-1]
    query, frac = descriptors.target_ring(np.stack([given.real, given.imag], axis=1))
    assert frac[0] == 0.0
    query = np.rint((_swap(query) if backwards else query) * descriptors.RING_QUANT)
    power, shift = descriptors.ring_match(stored, query)
    score = power[0] / (np.sum(stored * stored) * np.sum(query * query))
    assert score == pytest.approx(1.0, abs=1e-5)
    first = _arc_share(z, z[start] if not backwards else z[(start - 1) % 4000])
    assert min(abs(shift[0] - first), 1 - abs(shift[0] - first)) < 2e-3
    # the stretch descriptor depends on the start: the loop started between two of the eight
    # stored starts scores clearly lower against the nearest of them
    loops, _ = descriptors.target_descriptors(np.stack([z.real, z.imag], axis=1)[::4], closed=True, shifts=8)
    off, _ = descriptors.target_descriptors(np.roll(np.stack([z.real, z.imag], axis=1)[::4], -62, axis=0),
                                            closed=True)
    assert max(_similarity(off[0], loop) for loop in loops) < 1 - 1e-4


def _ring_reference(rows, query):
    """max over the start shift of |sum_k c_k conj(d_k) e^{2 pi i k s}|^2, by complex numpy on
    a fine grid (4,096 shifts) and a golden-section refinement: independent of ring_match."""
    m = descriptors.RING_ORDERS.size
    c = rows[:, :m] + 1j * rows[:, m:]
    d = query[:m] + 1j * query[m:]
    prod = c * np.conj(d)[None, :]
    s = np.arange(4096) / 4096

    def power(at):
        return np.abs(np.sum(prod[:, :, None] * np.exp(2j * np.pi * descriptors.RING_ORDERS[None, :, None]
                                                        * at[:, None, :]), axis=1)) ** 2
    grid = power(np.broadcast_to(s, (len(rows), len(s))))
    lo = (np.argmax(grid, axis=1) - 1) / 4096
    hi = lo + 2 / 4096
    g = (math.sqrt(5) - 1) / 2
    for _ in range(40):
        a, b = hi - g * (hi - lo), lo + g * (hi - lo)
        left = power(a[:, None])[:, 0] > power(b[:, None])[:, 0]
        hi, lo = np.where(left, b, hi), np.where(left, lo, a)
    return power(((lo + hi) / 2)[:, None])[:, 0]


def test_ring_match_against_a_reference_and_the_same_bits_in_any_row_order():
    rng = np.random.default_rng(11)
    rows = np.rint(rng.normal(size=(300, 4 * descriptors.RING_HARMONICS)) * 3000
                   / (1.0 + np.tile(np.abs(descriptors.RING_ORDERS), 2)))
    query = np.rint(rng.normal(size=4 * descriptors.RING_HARMONICS) * 3000
                    / (1.0 + np.tile(np.abs(descriptors.RING_ORDERS), 2)))
    power, shift = descriptors.ring_match(rows, query)
    np.testing.assert_allclose(power, _ring_reference(rows, query), rtol=2e-3)
    order = rng.permutation(len(rows))
    again, again_shift = descriptors.ring_match(rows[order], query)
    assert np.array_equal(again, power[order]) and np.array_equal(again_shift, shift[order])
    half, _ = descriptors.ring_match(rows[order[:7]], query)
    assert np.array_equal(half, power[order[:7]])


def test_the_shift_grid_product_is_exact_in_float64():
    """Products c_k conj(d_k) of two stored-size integers (below 2^30) times the integer
    twiddles: every sum below 2^53, so any BLAS order gives the exact integer."""
    rng = np.random.default_rng(3)
    top = 2 * descriptors.RING_QUANT ** 2
    p = rng.choice([-top, top], size=(500, 4 * descriptors.RING_HARMONICS)).astype(np.int64)
    exact = p @ descriptors.SHIFT_MATRIX.astype(np.int64)
    assert np.abs(exact).max() < 2 ** 53
    assert np.array_equal((p.astype(float) @ descriptors.SHIFT_MATRIX).astype(np.int64), exact)


def test_the_edge_stratum_is_small_cranks_at_the_crank_rockers_edge():
    linkages = family.draw(5000, 2)
    first = int(np.floor(family.CLASS_SHARES[0] * 5000)) + 5000 - sum(
        int(np.floor(s * 5000)) for s in family.CLASS_SHARES) - int(np.floor(family.EDGE_SHARE * 5000))
    edge = slice(first, first + int(np.floor(family.EDGE_SHARE * 5000)))
    a, b, c = linkages.lengths[edge].T
    assert np.all(linkages.kind[edge] == 0)
    codes = kin.grashof_code(a, b, c, 1.0)
    assert all(kin.GRASHOF_CLASSES[int(k)] == "crank-rocker" for k in codes)
    links = np.sort(np.stack([a, b, c, np.ones_like(a)]), axis=0)
    margin = 1 - (links[0] + links[3]) / (links[1] + links[2])
    assert margin.min() > 1e-7 and margin.max() < family.EDGE_MARGIN[1] * 1.001
    assert np.mean(margin < 1e-3) > 0.5  # most within 1e-3 of the change point, where the draws never go
    assert np.all((a >= family.EDGE_INPUT[0] * 0.999) & (a <= family.EDGE_INPUT[1] * 1.001))
    reach = np.hypot(*linkages.point[edge].T) / a
    assert reach.min() >= family.EDGE_POINT[0] * 0.999 and reach.max() <= family.EDGE_POINT[1] * 1.001
