"""Closed-form construction of the quick-return families (radians, lengths in the given scale).

Time ratio K = (pi + theta) / (pi - theta), so theta = pi (K - 1) / (K + 1): the angle between
the crank lines of the two dead centres (Hartenberg & Denavit, Kinematic Synthesis of
Linkages, sec. 7; Norton, Design of Machinery, sec. 3.6).

Crank-rocker. Frame: rocker pivot B0 at the origin, the rocker bisector along +x, the extreme
rocker pins B1 = c (cos h, sin h) (extended dead centre, |A0 B1| = r1 = b + a) and
B2 = c (cos h, -sin h) (folded, |A0 B2| = r2 = b - a), h = swing / 2, chord L = 2 c sin h.
The crank pivot A0 sees the chord B1 B2 under theta: in the triangle A0 B1 B2 the angle at A0
is theta; call gamma the angle at B1. Law of sines: r2 = L sin(gamma) / sin(theta) and
r1 = L sin(gamma + theta) / sin(theta).

Free parameter rho = +-r2 / L = +-(b - a) / |B1 B2|: the folded dead-centre distance over the
chord, negative when A0 lies on the rocker pivot's side of the chord line ("inner" arc: the
circle through B1, B2 whose centre is on B0's side), positive on the far side ("outer" arc, the
mirror image of the inner circle in the chord). Then sin(gamma) = |rho| sin(theta) and
r1 = L (|rho| cos(theta) + cos(gamma)): no division by sin(theta), so K = 1 (theta = 0, A0 on
the line B1 B2 beyond B2) is the same formula. rho -> 0 puts A0 on B2 (a = b).
b > a needs gamma < pi/2 - theta/2, i.e. |rho| < RHO_MAX = 1 / (2 sin(theta / 2)).
The lengths a, b depend on |rho| only; the sign moves A0 and so sets d.

The linkage has rocker extremes B1, B2 (swing exactly `swing`, time ratio exactly K) iff B1 and
B2 lie strictly on the same side of the line A0 B0 (then both dead centres belong to one
assembly; both triangles A0 B0 Bi exist, so |b - c| <= d - a and a + d <= b + c: the crank
turns fully and the output rocks). The side changes only where A0, B0 and B1 or B2 are
collinear; the law of sines in the triangle A0 B0 Bj (the other pin) gives those points:
collinear with B1: |rho| = cos(h) / sin(theta); with B2: |rho| = cos(h -+ theta) / sin(theta).
These break points cut (0, RHO_MAX) into pieces on which validity is constant; the valid
intervals are found by testing each piece's midpoint (valid_intervals).

Slider-crank (crank pivot at the origin, slider line y = e, stroke H): the same triangle with
the chord B1 B2 = H on the slider line. Free parameter rho = (b - a) / H in (0, cot(theta))
(right angle at B2 at the end: b - a = |e|): sin(gamma) = rho sin(theta),
r1 = H (rho cos(theta) + cos(gamma)), e = r1 sin(gamma) (distance of A0 from the line).
Given e instead: area and cosine rule of the triangle, r1 r2 sin(theta) = H |e| and
H^2 = r1^2 + r2^2 - 2 r1 r2 cos(theta), give
    4 a^2 = H^2 - 2 H |e| tan(theta / 2),   4 b^2 = H^2 + 2 H |e| cot(theta / 2),
valid (crank turns fully, b - a > |e|) iff 0 < |e| < H cot(theta) (K > 1; K = 1 needs e = 0).
"""

from __future__ import annotations

import numpy as np


def dead_centre_angle(time_ratio: float) -> float:
    """theta = pi (K - 1) / (K + 1): the angle between the two dead-centre crank lines."""
    return float(np.pi * (time_ratio - 1.0) / (time_ratio + 1.0))


def rho_max(theta: float) -> float:
    """|rho| bound where the crank length a = (r1 - r2) / 2 reaches 0: 1 / (2 sin(theta/2))."""
    return np.inf if theta == 0.0 else 0.5 / np.sin(0.5 * theta)


def crank_rocker_unit(rho, theta: float, swing: float, output: float = 1.0):
    """(a, b, c, d, A0x, A0y) for parameter rho, rocker length `output` (module docstring).

    Vectorized over rho; frame B0 = origin, rocker bisector +x."""
    rho = np.asarray(rho, dtype=float)
    h = 0.5 * swing
    chord = 2.0 * output * np.sin(h)
    r = np.abs(rho)
    sin_g = r * np.sin(theta)
    cos_g = np.sqrt(np.clip(1.0 - sin_g * sin_g, 0.0, None))
    r2 = chord * r
    r1 = chord * (r * np.cos(theta) + cos_g)
    sin_d = sin_g * np.cos(theta) + cos_g * np.sin(theta)    # sin(theta + gamma)
    cos_d = -(cos_g * np.cos(theta) - sin_g * np.sin(theta))  # -cos(theta + gamma)
    ax = output * np.cos(h) + np.sign(rho) * r2 * sin_d
    ay = -output * np.sin(h) + r2 * cos_d
    return 0.5 * (r1 - r2), 0.5 * (r1 + r2), np.full_like(r, output), np.hypot(ax, ay), ax, ay


def crank_rocker_break_points(theta: float, swing: float) -> list[float]:
    """|rho| where A0, B0 and B1 or B2 are collinear (inside (0, RHO_MAX)), sorted."""
    if theta == 0.0:
        return []
    h = 0.5 * swing
    top = rho_max(theta)
    pts = [np.cos(h) / np.sin(theta), np.cos(h - theta) / np.sin(theta),
           np.cos(h + theta) / np.sin(theta)]
    return sorted(float(p) for p in pts if 0.0 < p < top)


def same_side(rho, theta: float, swing: float):
    """True where B1 and B2 lie strictly on the same side of the line A0 B0."""
    h = 0.5 * swing
    *_, ax, ay = crank_rocker_unit(rho, theta, swing)
    cross1 = ax * np.sin(h) - ay * np.cos(h)     # A0 x B1 (c = 1)
    cross2 = -ax * np.sin(h) - ay * np.cos(h)    # A0 x B2
    return cross1 * cross2 > 0.0


def valid_intervals(theta: float, swing: float) -> list[tuple[float, float]]:
    """Open rho intervals (lo, hi), increasing, where the construction is a crank-rocker of
    the given K and swing. K = 1 gives [(0, inf)] (the mirror rho < 0 is the same linkage)."""
    if theta == 0.0:
        return [(0.0, np.inf)]
    cuts = [0.0] + crank_rocker_break_points(theta, swing) + [rho_max(theta)]
    out = []
    for sign in (-1.0, 1.0):
        for lo, hi in zip(cuts[:-1], cuts[1:]):
            if hi > lo and bool(same_side(sign * 0.5 * (lo + hi), theta, swing)):
                out.append((-hi, 0.0 - lo) if sign < 0 else (lo, hi))  # 0.0 - 0.0 is +0.0
    out.sort()
    merged: list[tuple[float, float]] = []
    for lo, hi in out:  # neighbours that meet at a spurious break point are one interval
        if merged and merged[-1][1] == lo and lo != 0.0:
            merged[-1] = (merged[-1][0], hi)
        else:
            merged.append((lo, hi))
    return merged


def slider_crank_unit(rho, theta: float, stroke: float):
    """(a, b, e) of the free-offset slider-crank family at rho = (b - a) / H (e >= 0)."""
    r = np.asarray(rho, dtype=float)
    sin_g = r * np.sin(theta)
    cos_g = np.sqrt(np.clip(1.0 - sin_g * sin_g, 0.0, None))
    r2 = stroke * r
    r1 = stroke * (r * np.cos(theta) + cos_g)
    return 0.5 * (r1 - r2), 0.5 * (r1 + r2), r1 * sin_g


def slider_rho_max(theta: float) -> float:
    """End of the slider family: cot(theta) (b - a = |e|, the crank just turns); inf at K = 1."""
    return np.inf if theta == 0.0 else float(np.cos(theta) / np.sin(theta))


def slider_crank_with_offset(stroke: float, theta: float, offset: float) -> tuple[float, float]:
    """(crank a, rod b) of the unique slider-crank with stroke H, angle theta, offset e
    (0 < |e| < H cot(theta); module docstring)."""
    e = abs(offset)
    t = np.tan(0.5 * theta)
    a = 0.5 * np.sqrt(stroke * stroke - 2.0 * stroke * e * t)
    b = 0.5 * np.sqrt(stroke * stroke + 2.0 * stroke * e / t)
    return float(a), float(b)
