"""Burmester theory: four poses give a one-parameter family of dyads (the centre-point
and circle-point curves), five poses a finite set (the Burmester points).

With the bilinear dyad equations f_i(G, M) = 0 of dyads.py, rows
K(G) = [m_i + B_i G, k_i + g_i . G] make K(G) (M, 1)^T = 0. A centre point G admits a
moving pivot iff K(G) has rank <= 2:

* four poses: K is 3 x 3 and det K(G) = 0 is a cubic curve, the centre-point curve; its
  matched M (the null vector of K(G)) trace the circle-point curve. The curve passes
  through the six poles P_jk (Sandor & Erdman, Advanced Mechanism Design vol. 2, sec. 3.3;
  McCarthy & Soh, Geometric Design of Linkages, ch. 4).
* five poses: the centre points lie on both cubics C_1234 and C_1235. By Bezout they meet
  in 9 points of the complex projective plane: the three poles P12, P13, P23 that both
  curves contain, the two circular points at infinity (both cubics are circular), and the
  four Burmester points. Eliminating y with the Sylvester resultant gives R(x), of degree
  at most 9; every finite common point is a root of R. np.roots returns ALL complex roots
  of R, so no real Burmester point can be missed (completeness); each real root is lifted
  to (G, M), polished by Newton on the full five-pose system f_2..f_5 = 0 (4 equations,
  4 unknowns) and kept only if it solves it: the poles solve the two cubics but not the
  full system (at P12, f_2 vanishes identically and three equations remain for the two
  unknowns of M), so they drop out. Coordinates are first centred, scaled and turned by a
  fixed generic angle, so that no two intersection points share x; the lift is repeated
  from a second such angle and the results merged, which covers the non-generic case.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations

import numpy as np

from .dyads import coefficients
from .poses import as_poses, characteristic_length, pole, poles

GENERIC_ANGLES = (0.5, 1.3)  # rad: rotations of the frame before the elimination in x
SOLVE_TOL = 1e-11  # |f| (normalized lengths squared) for an accepted Burmester dyad
SAME_DYAD = 1e-7  # normalized distance: two roots lifted to the same dyad
NEAR_REAL = 1e-3  # relative imaginary part of a root still worth a real Newton polish


# ---------------------------------------------------------------- normalization

@dataclass
class Frame:
    """Normalized coordinates: p' = R(turn) (p - centre) / scale, body points m' = m / scale,
    angles + turn. Every solver works in them; results map back with to_world."""

    centre: np.ndarray
    scale: float
    turn: float

    def poses(self, poses):
        c, s = np.cos(self.turn), np.sin(self.turn)
        d = (poses[:, :2] - self.centre) / self.scale
        return np.column_stack([c * d[:, 0] - s * d[:, 1], s * d[:, 0] + c * d[:, 1],
                                poses[:, 2] + self.turn])

    def to_world(self, ground, moving):
        c, s = np.cos(self.turn), np.sin(self.turn)
        gx, gy = ground[..., 0], ground[..., 1]
        world = np.stack([c * gx + s * gy, -s * gx + c * gy], -1) * self.scale + self.centre
        return world, moving * self.scale


def normal_frame(poses, turn=0.0) -> Frame:
    poses = as_poses(poses)
    return Frame(poses[:, :2].mean(0), characteristic_length(poses), float(turn))


def det_pencil(a, b):
    """Coefficients [c0, c1, c2, c3] of det(a + s b) for 3 x 3 matrices (broadcast), by
    multilinearity in the columns: c_k sums the determinants with k columns taken from b,
    each the triple product det[x, y, z] = x . (y x z) (elementwise: the same bits on
    every machine, and one pass over the stack instead of eight LAPACK determinants)."""
    a, b = np.broadcast_arrays(np.asarray(a), np.asarray(b))
    a1, a2, a3 = a[..., :, 0], a[..., :, 1], a[..., :, 2]
    b1, b2, b3 = b[..., :, 0], b[..., :, 1], b[..., :, 2]
    a23, b23 = _cross(a2, a3), _cross(b2, b3)
    mixed = _cross(b2, a3) + _cross(a2, b3)
    return np.stack([_dot3(a1, a23), _dot3(b1, a23) + _dot3(a1, mixed),
                     _dot3(a1, b23) + _dot3(b1, mixed), _dot3(b1, b23)], -1)


def _cross(x, y):
    """x x y over the last axis (length 3), elementwise."""
    return np.stack([x[..., 1] * y[..., 2] - x[..., 2] * y[..., 1],
                     x[..., 2] * y[..., 0] - x[..., 0] * y[..., 2],
                     x[..., 0] * y[..., 1] - x[..., 1] * y[..., 0]], -1)


def _dot3(x, y):
    """x . y over the last axis (length 3), summed left to right."""
    return x[..., 0] * y[..., 0] + x[..., 1] * y[..., 1] + x[..., 2] * y[..., 2]


# ---------------------------------------------------------------- four poses

@dataclass
class CentrePointCurve:
    """Samples of the four-pose curves. parameter (T,): direction t of the line through
    P12 cutting the cubic; ground (T, 2, 2): the two other cuts (branch axis 1), i.e. the
    centre-point curve; moving (T, 2, 2): matched moving pivots (body frame), circle
    (T, 2, 2): the same at pose 1 (global), i.e. the circle-point curve. NaN where a cut
    is complex or beyond max_distance. poles (6, 2): P12, P13, P14, P23, P24, P34, on the
    centre-point curve (there two moving-pivot positions share a circle trivially);
    asymptotes: directions t where a cut runs to infinity (the real asymptote)."""

    parameter: np.ndarray
    ground: np.ndarray
    moving: np.ndarray
    circle: np.ndarray
    poles: np.ndarray
    asymptotes: np.ndarray

    def pairs(self):
        """Finite samples as matched arrays (G (K, 2), M (K, 2))."""
        g = self.ground.reshape(-1, 2)
        m = self.moving.reshape(-1, 2)
        ok = np.all(np.isfinite(g), -1) & np.all(np.isfinite(m), -1)
        return g[ok], m[ok]


def _moving_from_rows(rows):
    """M from the null vector of rank-2 rows (..., r, 3): the largest cross product of two rows."""
    r = rows.shape[-2]
    crosses = np.stack([np.cross(rows[..., i, :], rows[..., j, :])
                        for i, j in combinations(range(r), 2)], -2)
    best = np.argmax(np.linalg.norm(crosses, axis=-1), -1)
    v = np.take_along_axis(crosses, best[..., None, None], -2)[..., 0, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        return v[..., :2] / v[..., 2:3]


def _gauss_newton(coef, ground, moving, iterations=4):
    """Minimum-norm Gauss-Newton steps on f(G, M) = 0 (vectorized; rows <= 4 unknowns)."""
    for _ in range(iterations):
        f = coef.residuals(ground, moving)
        jac = coef.jacobian(ground, moving)
        bad = ~np.all(np.isfinite(jac), (-1, -2)) | ~np.all(np.isfinite(f), -1)
        jac = np.where(bad[..., None, None], 0.0, jac)
        step = -np.einsum("...ij,...j->...i", np.linalg.pinv(jac), np.where(bad[..., None], 0.0, f))
        ground = ground + step[..., :2]
        moving = moving + step[..., 2:]
    return ground, moving


def centre_point_curve(poses, samples=721, max_distance=10.0) -> CentrePointCurve:
    """Sample the centre-point and circle-point curves of four poses (n = 4, rad).

    Lines G = P12 + s (cos t, sin t), t in [0, pi), meet the cubic det K(G) = 0 at s = 0
    (the pole) and at the roots of c3 s^2 + c2 s + c1 (det_pencil); each cut is matched
    with its M (null vector of K(G)) and polished by Gauss-Newton on f_2..f_4 = 0.
    max_distance: in characteristic lengths from the pose centroid; farther cuts are NaN."""
    poses = as_poses(poses)
    if len(poses) != 4:
        raise ValueError("centre_point_curve needs exactly four poses")
    frame = normal_frame(poses)
    npz = frame.poses(poses)
    coef = coefficients(npz)
    p12 = pole(npz[0], npz[1])
    t = np.linspace(0.0, np.pi, samples, endpoint=False)
    e = np.stack([np.cos(t), np.sin(t)], -1)
    k0 = coef.moving_rows(p12)
    k1 = coef.moving_rows(p12 + e) - k0
    c = det_pencil(k0, k1)  # c0 ~ 0: the pole
    qa, qb, qc = c[:, 3], c[:, 2], c[:, 1]
    disc = qb * qb - 4 * qa * qc
    real = disc >= 0
    sq = np.sqrt(np.where(real, disc, 0.0))
    big = -0.5 * (qb + np.where(qb >= 0, sq, -sq))  # stable quadratic roots
    with np.errstate(divide="ignore", invalid="ignore"):
        s1 = np.where(big != 0, big / qa, np.nan)
        s2 = np.where(big != 0, qc / big, np.nan)
    s = np.where(real[:, None], np.stack([s1, s2], -1), np.nan)
    ground = p12 + s[..., None] * e[:, None, :]
    moving = _moving_from_rows(coef.moving_rows(ground))
    ground, moving = _gauss_newton(coef, ground, moving)
    far = (np.linalg.norm(ground, axis=-1) > max_distance) | ~np.all(np.isfinite(moving), -1)
    ground = np.where(far[..., None], np.nan, ground)
    moving = np.where(far[..., None], np.nan, moving)
    g_world, m_world = frame.to_world(ground, moving)
    c_, s_ = np.cos(poses[0, 2]), np.sin(poses[0, 2])
    circle = np.stack([c_ * m_world[..., 0] - s_ * m_world[..., 1] + poses[0, 0],
                       s_ * m_world[..., 0] + c_ * m_world[..., 1] + poses[0, 1]], -1)
    all_poles = poles(poses)
    pole_list = np.array([all_poles[i, j] for i, j in combinations(range(4), 2)])
    sign = np.sign(qa)
    flips = np.nonzero(sign[1:] * sign[:-1] < 0)[0]
    return CentrePointCurve(t, g_world, m_world, circle, pole_list, t[flips])


# ---------------------------------------------------------------- five poses

@dataclass
class BurmesterResult:
    """All real Burmester dyads of five poses. ground, moving: (K, 2) each, K <= 4 (K = 6
    only in degenerate data); residual: (K,) max |f_i| (length^2) after polishing;
    resultant_degree: numerical degree of R(x) (7 for general data: 9 minus the two
    circular points); roots: number of complex roots of R examined; pole_roots: roots
    that are the poles P12, P13, P23."""

    ground: np.ndarray
    moving: np.ndarray
    residual: np.ndarray
    resultant_degree: int
    roots: int
    pole_roots: int


def _sylvester_det(p, q):
    """Resultant of two cubics in y given by coefficients (..., 4) low -> high."""
    shape = p.shape[:-1]
    syl = np.zeros(shape + (6, 6), dtype=np.result_type(p, q))
    for r in range(3):
        syl[..., r, r:r + 4] = p[..., ::-1]
        syl[..., 3 + r, r:r + 4] = q[..., ::-1]
    return np.linalg.det(syl)


def _newton(coef, ground, moving, iterations=12):
    """Newton on the square system f_2..f_5 = 0 (4 x 4), vectorized over candidates (each
    with its own coefficients when `coef` holds one set a candidate: Coefficients.take)."""
    for _ in range(iterations):
        f = coef.residuals(ground, moving)
        jac = coef.jacobian(ground, moving)
        ok = np.abs(np.linalg.det(jac)) > 1e-300
        step = np.linalg.solve(np.where(ok[..., None, None], jac, np.eye(4)),
                               np.where(ok[..., None], f, 0.0)[..., None])[..., 0]
        ground = ground - step[..., :2]
        moving = moving - step[..., 2:]
    return ground, moving


def _lift(coef):
    """Candidate (G, M) from the real roots of the resultant, for a stack of S pose sets in
    one normalized frame each (`coef`: their coefficients, (S, 4, ...)): the resultants of
    every set side by side, the roots set by set. Returns (G (C, 2), M (C, 2), the set of
    each candidate (C,), the resultants' degrees (S,), their root counts (S,))."""
    sets = len(coef.k)
    kx00 = coef.moving_rows(np.zeros((sets, 2)))
    kx = coef.moving_rows(np.tile([1.0, 0.0], (sets, 1))) - kx00
    ky = coef.moving_rows(np.tile([0.0, 1.0], (sets, 1))) - kx00
    rows_a, rows_b = [0, 1, 2], [0, 1, 3]

    def cubics(x, own):  # the two cubics in y at x (..., ), each x of the set own (...,)
        base = kx00[own] + x[..., None, None] * kx[own]
        return (det_pencil(base[..., rows_a, :], ky[own][..., rows_a, :]),
                det_pencil(base[..., rows_b, :], ky[own][..., rows_b, :]))

    n = 32
    xs = np.exp(2j * np.pi * np.arange(n) / n)
    every = np.arange(sets)[:, None]
    pa, pb = cubics(np.broadcast_to(xs, (sets, n)), np.broadcast_to(every, (sets, n)))
    res = _sylvester_det(pa, pb)
    coeffs = np.fft.fft(res).real / n  # R(x) = sum coeffs[j] x^j on the unit circle, a row a set
    top = np.max(np.abs(coeffs), axis=1)
    degrees, counts, xr, x_set = np.zeros(sets, int), np.zeros(sets, int), [], []
    for k, (row, roots) in enumerate(zip(coeffs, roots_many(coeffs[:, :10][:, ::-1]))):
        significant = np.nonzero(np.abs(row) > 1e-9 * top[k])[0]
        degrees[k] = int(significant[-1]) if len(significant) else 0
        roots = roots if top[k] > 0 else np.zeros(0)
        counts[k] = len(roots)
        near_real = np.abs(roots.imag) <= NEAR_REAL * (1 + np.abs(roots))
        xr.append(roots.real[near_real])
        x_set.append(np.full(int(np.sum(near_real)), k))
    xr, x_set = np.concatenate(xr), np.concatenate(x_set).astype(int)
    ya, _ = cubics(xr, x_set)  # the first cubic in y at every real root at once
    grounds, owner = [], []
    for x, k, ys in zip(xr, x_set, roots_many(ya[:, ::-1])):  # at most 9 roots a set, 3 y each
        for y in ys:
            if abs(y.imag) <= NEAR_REAL * (1 + abs(y)):
                grounds.append([x, y.real])
                owner.append(k)
    ground, owner = np.array(grounds, float).reshape(-1, 2), np.array(owner, int)
    if len(ground) == 0:
        return ground, ground.copy(), owner, degrees, counts
    k = coef.take(owner).moving_rows(ground)
    v = np.linalg.svd(k)[2][:, -1, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        moving = v[:, :2] / v[:, 2:3]
    return ground, moving, owner, degrees, counts


def roots_many(polys) -> list[np.ndarray]:
    """np.roots of each row of polys (P, N), highest power first: the eigenvalues of the
    companion matrices, as np.roots forms them, of every row whose first and last
    coefficients are not 0 in one LAPACK call on their stack (the same matrices, so the
    same roots); the others by np.roots itself (it trims their zeros)."""
    polys = np.asarray(polys)
    out = [None] * len(polys)
    plain = (polys[:, 0] != 0) & (polys[:, -1] != 0) if polys.shape[1] > 1 else np.zeros(len(polys), bool)
    for k in np.flatnonzero(~plain):
        out[k] = np.roots(polys[k])
    rows = np.flatnonzero(plain)
    if len(rows):
        p = polys[rows]
        size = p.shape[1] - 1
        companion = np.zeros((len(rows), size, size), p.dtype)
        companion[:, np.arange(1, size), np.arange(size - 1)] = 1
        companion[:, 0, :] = -p[:, 1:] / p[:, :1]
        for k, roots in zip(rows, np.linalg.eigvals(companion)):
            out[k] = roots
    return out


def burmester_dyads(poses) -> BurmesterResult:
    """All real dyads through five poses (n = 5, angles in rad), see module docstring."""
    poses = as_poses(poses)
    if len(poses) != 5:
        raise ValueError("burmester_dyads needs exactly five poses")
    return burmester_dyads_many(poses[None])[0]


def burmester_dyads_many(pose_sets) -> list[BurmesterResult]:
    """`burmester_dyads` of each of S five-pose sets (S, 5, 3): the sets' resultants, lifts
    and Newton polishes side by side (one numpy call for all where the previous set-by-set
    calls were many), their roots and merges set by set."""
    sets = np.asarray(pose_sets, float)
    if sets.ndim != 3 or sets.shape[1:] != (5, 3):
        raise ValueError("burmester_dyads needs sets of exactly five poses")
    count = len(sets)
    if count == 0:
        return []
    found_g, found_m = [[] for _ in range(count)], [[] for _ in range(count)]
    degree, nroots, pole_roots = np.zeros(count, int), np.zeros(count, int), np.zeros(count, int)
    for turn in GENERIC_ANGLES:
        frames = [normal_frame(p, turn) for p in sets]
        npz = np.stack([frame.poses(p) for frame, p in zip(frames, sets)])
        coef = coefficients(npz)
        g0, m0, owner, deg, nr = _lift(coef)
        degree, nroots = np.maximum(degree, deg), np.maximum(nroots, nr)
        if turn == GENERIC_ANGLES[0]:
            for k in range(count):
                shared = np.array([pole(npz[k, i], npz[k, j]) for i, j in ((0, 1), (0, 2), (1, 2))])
                mine = g0[owner == k]
                pole_roots[k] = int(np.sum(np.any(np.linalg.norm(
                    mine[:, None, :] - shared[None], axis=-1) < 1e-6, 0))) if len(mine) else 0
        ok0 = np.all(np.isfinite(m0), -1)
        own = owner[ok0]
        mine_coef = coef.take(own)  # each candidate's set's coefficients
        g, m = _newton(mine_coef, g0[ok0], m0[ok0])
        f = np.max(np.abs(mine_coef.residuals(g, m)), -1) if len(g) else np.zeros(0)
        good = np.isfinite(f) & (f <= SOLVE_TOL)
        for k in range(count):
            mine = good & (own == k)
            gw, mw = frames[k].to_world(g[mine], m[mine])
            found_g[k].append(gw)
            found_m[k].append(mw)
    return [_merged(sets[k], found_g[k], found_m[k], int(degree[k]), int(nroots[k]), int(pole_roots[k]))
            for k in range(count)]


def _merged(poses, found_g, found_m, degree, nroots, pole_roots) -> BurmesterResult:
    """One set's dyads from both frames, each once (SAME_DYAD), ordered by ground pivot."""
    ground = np.concatenate(found_g).reshape(-1, 2)
    moving = np.concatenate(found_m).reshape(-1, 2)
    scale = characteristic_length(poses)
    key = np.concatenate([ground, moving], -1)
    diff = key[:, None, :] - key[None, :, :]
    apart = np.sqrt(np.einsum("ijk,ijk->ij", diff, diff)) > (
        SAME_DYAD * scale * (1 + np.sqrt(np.einsum("ik,ik->i", key, key)) / scale))[:, None]
    keep = []
    for i in range(len(ground)):  # each dyad apart from every one kept before it (a few a set)
        if apart[i, keep].all():
            keep.append(i)
    ground, moving = ground[keep], moving[keep]
    order = np.lexsort((ground[:, 1], ground[:, 0]))
    ground, moving = ground[order], moving[order]
    full = coefficients(poses)
    residual = np.max(np.abs(full.residuals(ground, moving)), -1) if len(ground) else np.zeros(0)
    return BurmesterResult(ground, moving, residual, degree, nroots, pole_roots)
