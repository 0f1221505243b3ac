"""The atlas's four-bars and their coupler curves (numpy; `portable` arithmetic only).

A four-bar of the atlas: ground d = 1 (A0 at the origin, B0 at (1, 0), the conventions
of docs/format.md), input a, coupler b, output c, coupler point (px, py) in the coupler
frame, branch sign (-1 open, +1 crossed). Drawn from a seeded numpy Generator (PCG64: the
same stream on every machine), every value rounded to float32 (what the file stores),
then used as drawn:

* a, b, c log-uniform in [LENGTH_LO, LENGTH_HI] (relative to the ground), classified
  (Grashof, docs/format.md), kept in order of drawing until each class has its share
  (CLASS_SHARES); lengths within CHANGE_POINT of a change point are dropped (their curves
  turn at a toggle that a search cannot hold);
* the coupler point uniform in a disc of radius POINT_RADIUS b about the coupler's middle;
* the branch: each with probability 1/2;
* and a stratum of its own, EDGE_SHARE of the atlas, kept among the crank-rockers (after
  the others; `draw_edge`): small cranks at the crank-rocker's edge, the input log-uniform
  in EDGE_INPUT, s + l = (p + q)(1 - m) with the margin m log-uniform in EDGE_MARGIN (the
  longest of ground, coupler and output, each a third of the time, solved from the
  others), the coupler point at a distance from the crank pin of EDGE_POINT inputs
  (log-uniform, any direction). Near the change point the coupler swings fast where the
  coupler and output nearly fold, and the curve of a point near the crank pin is the
  crank's circle with a corner there: shapes of free-timing optima (they often sit on
  that edge: the search's Grashof margin) that the draws above, clear of the change point
  and with the point anywhere on a coupler many inputs long, almost never hold.

A turning input (crank-rocker, double-crank) traces a closed curve over one turn:
SAMPLES input angles 2 pi j / SAMPLES. A rocking input (rocker-crank, double-rocker,
triple-rocker) traces an open curve between its two dead points on one branch (the
arc through phi in (0, pi) when there are two: the other is the mirror image of a
linkage of the other branch): SAMPLES + 1 angles spaced as (1 - cos(pi t)) / 2, dense
where the coupler point moves as the square root of the angle. That open curve is all
that free timing can use of a rocking input (no dead point between the targets).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from linkcli.atlas import portable

CLASSES = ("crank-rocker", "double-crank", "rocker-crank", "double-rocker", "triple-rocker")
TURNING = (0, 1)  # class codes whose input turns fully: closed curves
CLASS_SHARES = (0.33, 0.14, 0.16, 0.10, 0.19)  # of the atlas's four-bars, in CLASSES order,
EDGE_SHARE = 0.08  # and the small cranks at the crank-rocker's edge (crank-rockers too)
EDGE_INPUT = (0.005, 0.12)  # their input relative to the ground
EDGE_MARGIN = (1e-6, 3e-2)  # 1 - (s + l) / (p + q) (float32 lengths keep above 1e-7)
EDGE_POINT = (0.3, 30.0)  # their coupler point's distance from the crank pin, in inputs
LENGTH_LO, LENGTH_HI = 0.12, 5.0  # input, coupler, output relative to the ground
POINT_RADIUS = 1.5  # coupler points within this many coupler lengths of the coupler's middle
CHANGE_POINT = 1e-3  # relative: |s + l - p - q| below this share of p + q is dropped
SAMPLES = 256  # curve samples (a rocking input: SAMPLES + 1, both dead points included)
ASSEMBLY_SLACK = 1e-9  # |cos alpha| may pass 1 by round-off this much at a dead point


@dataclass
class Linkages:
    """Atlas four-bars (N rows), ground 1: lengths (N, 3) a, b, c; point (N, 2) px, py;
    sign (N,) -1 open, +1 crossed; kind (N,) class code (CLASSES)."""

    lengths: np.ndarray
    point: np.ndarray
    sign: np.ndarray
    kind: np.ndarray

    def __len__(self) -> int:
        return len(self.kind)

    def take(self, rows) -> Linkages:
        return Linkages(self.lengths[rows], self.point[rows], self.sign[rows], self.kind[rows])

    @property
    def closed(self) -> np.ndarray:
        return np.isin(self.kind, TURNING)


def classify(a, b, c, d=1.0) -> tuple[np.ndarray, np.ndarray]:
    """(class code, usable) of each row (docs/format.md, Grashof): usable when clear of a
    change point and when it assembles somewhere (the longest link shorter than the other
    three together, by CHANGE_POINT: a triple-rocker may not)."""
    links = np.stack(np.broadcast_arrays(d, a, b, c), axis=1)
    srt = np.sort(links, axis=1)
    s_l, p_q = srt[:, 0] + srt[:, 3], srt[:, 1] + srt[:, 2]
    shortest = np.argmin(links, axis=1)  # 0 ground, 1 input, 2 coupler, 3 output
    grashof_code = np.array([1, 0, 3, 2])[shortest]  # double-crank, crank-rocker, double-rocker, rocker-crank
    code = np.where(s_l < p_q, grashof_code, 4)
    assembles = srt[:, 3] < (srt[:, 0] + p_q) * (1.0 - CHANGE_POINT)  # l < s + p + q
    return code, (np.abs(s_l - p_q) > CHANGE_POINT * p_q) & assembles


def draw(size: int, seed: int) -> Linkages:
    """`size` four-bars, CLASS_SHARES of each class (the first drawn of each) and EDGE_SHARE
    of small cranks at the crank-rocker's edge (`draw_edge`), in the order: the
    crank-rockers, the edge's, then every other class in turn, each in the order drawn.
    Deterministic in (size, seed)."""
    rng = np.random.default_rng([seed, 50])
    want = np.floor(np.array(CLASS_SHARES) * size).astype(int)
    edge = int(np.floor(EDGE_SHARE * size))
    want[0] += size - want.sum() - edge
    kept: list[list[np.ndarray]] = [[] for _ in CLASSES]
    have = np.zeros(len(CLASSES), dtype=int)
    lo, hi = np.log(LENGTH_LO), np.log(LENGTH_HI)
    while np.any(have < want):
        n = 4 * size + 1000
        lengths = np.exp(lo + (hi - lo) * rng.random((n, 3))).astype(np.float32).astype(float)
        radius = POINT_RADIUS * np.sqrt(rng.random(n))
        angle_sin, angle_cos = portable.sincos(2.0 * portable.PI * rng.random(n))
        sign = np.where(rng.random(n) < 0.5, -1.0, 1.0)
        b = lengths[:, 1]
        point = np.stack([b * (0.5 + radius * angle_cos), b * radius * angle_sin], axis=1)
        point = point.astype(np.float32).astype(float)
        code, clear = classify(lengths[:, 0], lengths[:, 1], lengths[:, 2])
        for k in range(len(CLASSES)):
            rows = np.flatnonzero((code == k) & clear)[:want[k] - have[k]]
            kept[k].append(np.concatenate([lengths[rows], point[rows], sign[rows, None]], axis=1))
            have[k] += len(rows)
    parts = [np.concatenate(kept[0]), draw_edge(rng, edge)] + [np.concatenate(p) for p in kept[1:]]
    table = np.concatenate(parts)
    kind = np.repeat(np.arange(len(CLASSES)), want + np.eye(len(CLASSES), dtype=int)[0] * edge)
    return Linkages(table[:, :3], table[:, 3:5], table[:, 5], kind.astype(np.int8))


def draw_edge(rng: np.random.Generator, count: int) -> np.ndarray:
    """(count, 6) rows (a, b, c, px, py, sign) of small cranks at the crank-rocker's edge
    (module docstring), float32 values; only rows that stay crank-rockers (s + l below
    (p + q)(1 - 1e-7), the input the shortest) once rounded are kept, in the order drawn."""
    kept, have = [], 0
    while have < count:
        n = 2 * count + 1000
        u = rng.random((n, 6))
        a = np.exp(np.log(EDGE_INPUT[0]) + np.log(EDGE_INPUT[1] / EDGE_INPUT[0]) * u[:, 0])
        m = np.exp(np.log(EDGE_MARGIN[0]) + np.log(EDGE_MARGIN[1] / EDGE_MARGIN[0]) * u[:, 1])
        other = np.exp(np.log(LENGTH_LO) + np.log(LENGTH_HI / LENGTH_LO) * u[:, 2])
        longest = np.floor(3.0 * u[:, 3]).astype(int)  # 0 ground, 1 coupler, 2 output
        # ground the longest: b + c = (1 + a) / (1 - m), b drawn within that sum; coupler
        # (output) the longest: it is (1 + the other)(1 - m) - a
        total = (1.0 + a) / (1.0 - m)
        b = np.where(longest == 0, total * (0.5 + (u[:, 2] - 0.5) * 0.98),
                     np.where(longest == 1, (1.0 + other) * (1.0 - m) - a, other))
        c = np.where(longest == 0, total - b, np.where(longest == 1, other, (1.0 + other) * (1.0 - m) - a))
        radius = a * np.exp(np.log(EDGE_POINT[0]) + np.log(EDGE_POINT[1] / EDGE_POINT[0]) * u[:, 4])
        turn_sin, turn_cos = portable.sincos(2.0 * portable.PI * u[:, 5])
        sign = np.where(rng.random(n) < 0.5, -1.0, 1.0)
        lengths = np.stack([a, b, c], axis=1).astype(np.float32).astype(float)
        point = np.stack([radius * turn_cos, radius * turn_sin], axis=1).astype(np.float32).astype(float)
        srt = np.sort(np.concatenate([np.ones((n, 1)), lengths], axis=1), axis=1)
        fine = ((np.argmin(np.concatenate([lengths[:, :1], np.ones((n, 1)), lengths[:, 1:]], axis=1), axis=1) == 0)
                & (srt[:, 0] + srt[:, 3] < (srt[:, 1] + srt[:, 2]) * (1.0 - 1e-7)) & (lengths > 0.0).all(axis=1))
        rows = np.flatnonzero(fine)[:count - have]
        kept.append(np.concatenate([lengths[rows], point[rows], sign[rows, None]], axis=1))
        have += len(rows)
    return np.concatenate(kept) if kept else np.zeros((0, 6))


def rocking_range(a, b, c, d=1.0) -> tuple[np.ndarray, np.ndarray]:
    """(lo, hi) of a rocking input's reachable arc through phi in [0, pi] (rad), as
    kinematics.input_arcs: rho^2 = (a - d)^2 + 4 a d sin^2(phi / 2) within
    [(b - c)^2, (b + c)^2]; an end at rho = r lies at 2 atan2(sqrt(N), sqrt(M)),
    N = (r - |a - d|)(r + |a - d|), M = (a + d - r)(a + d + r)."""
    a, b, c, d = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (a, b, c, d)))
    near, far = np.abs(a - d), a + d
    r_lo, r_hi = np.abs(b - c), b + c

    def end(r):
        n = np.maximum((r - near) * (r + near), 0.0)
        m = np.maximum((far - r) * (far + r), 0.0)
        return 2.0 * portable.atan2(np.sqrt(n), np.sqrt(m))

    g_hi, g_lo = end(r_hi), end(r_lo)
    through_0 = r_lo <= near  # one arc (-g_hi, g_hi): its upper half is not enough, take it whole
    through_pi = r_hi >= far  # one arc (g_lo, 2 pi - g_lo)
    lo = np.where(through_0, -g_hi, g_lo)
    hi = np.where(through_0, g_hi, np.where(through_pi, 2.0 * portable.PI - g_lo, g_hi))
    return lo, hi


def input_angles(linkages: Linkages, samples: int = SAMPLES) -> np.ndarray:
    """(N, S) input angles of each curve's samples (rad, increasing): a full turn for a
    turning input (S = samples), the reachable arc with both ends for a rocking one
    (S = samples + 1; the closed ones then repeat their first angle + 2 pi last, so that
    every row has samples + 1 points and every curve is a polyline from its first to
    its last sample)."""
    t = np.arange(samples + 1) / samples
    _, cos_pi_t = portable.sincos(portable.PI * t)
    a, b, c = linkages.lengths.T
    lo, hi = rocking_range(a, b, c)
    closed = linkages.closed
    lo, hi = np.where(closed, 0.0, lo), np.where(closed, 2.0 * portable.PI, hi)
    spacing = np.where(closed[:, None], t[None, :], (0.5 * (1.0 - cos_pi_t))[None, :])
    return lo[:, None] + (hi - lo)[:, None] * spacing


def angle_sines(linkages: Linkages, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(sin phi, cos phi) of `input_angles`: the closed rows share one grid, computed once."""
    closed = linkages.closed
    sphi, cphi = np.empty_like(phi), np.empty_like(phi)
    if closed.any():
        grid = portable.sincos(phi[np.flatnonzero(closed)[0]])
        sphi[closed], cphi[closed] = grid
    if not closed.all():
        sphi[~closed], cphi[~closed] = portable.sincos(phi[~closed])
    return sphi, cphi


def coupler_points(linkages: Linkages, phi: np.ndarray, sines=None) -> tuple[np.ndarray, np.ndarray]:
    """Coupler point (x, y), each (N, S), in the frame of A0 and B0 at input angles phi
    (N, S) (`sines`: their sines and cosines, when known), on each row's branch: the closure of mechanisms.four_bar.closure with
    `portable` functions (A = a e^{i phi}, rho e^{i theta_rho} = A - d,
    cos alpha = (rho^2 + c^2 - b^2) / (2 rho c), e^{i psi} = e^{i theta_rho}(cos alpha +
    i sign sin alpha), e^{i theta} = (d + c e^{i psi} - A) / |.|, P = A + p e^{i theta})."""
    a, b, c = (linkages.lengths[:, k:k + 1] for k in range(3))
    px, py = linkages.point[:, 0:1], linkages.point[:, 1:2]
    sign = linkages.sign[:, None]
    sphi, cphi = portable.sincos(phi) if sines is None else sines
    ax, ay = a * cphi, a * sphi
    rx = ax - 1.0
    rho = portable.norm(rx, ay)
    safe = np.where(rho > 0.0, rho, 1.0)
    ca = np.clip((rho * rho + c * c - b * b) / (safe * (2.0 * c)), -1.0, 1.0)
    sa = sign * np.sqrt((1.0 - ca) * (1.0 + ca))
    ux, uy = rx / safe, ay / safe
    cpsi, spsi = ux * ca - uy * sa, uy * ca + ux * sa
    bx, by = 1.0 + c * cpsi - ax, c * spsi - ay
    length = portable.norm(bx, by)
    length = np.where(length > 0.0, length, 1.0)
    ct, st = bx / length, by / length
    return ax + px * ct - py * st, ay + px * st + py * ct
