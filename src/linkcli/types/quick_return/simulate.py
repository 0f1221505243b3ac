"""Time ratio and swing (or stroke) recomputed from a linkage's lengths, in closed form.

Used to report achieved values rather than echo the requested ones.

Four-bar (A0 at the origin, B0 at (d, 0), crank a, coupler b, rocker c): at the dead centres
A0, A, B are collinear with |A0 B| = b + a (extended) or b - a (folded). The cosine rule in the
triangle A0 B0 B gives the angle of A0 B from the ground line, alpha(r) = acos((d^2 + r^2 - c^2)
/ (2 d r)), and the rocker angle at B0, beta(r) = acos((d^2 + c^2 - r^2) / (2 d c)). On one
assembly branch the crank points along A0 B1 at the extended dead centre and against A0 B2 at
the folded one, so the crank turns pi + theta one way and pi - theta the other with
theta = |alpha(b - a) - alpha(b + a)|: K = (pi + theta) / (pi - theta), and the rocker swings
|beta(b + a) - beta(b - a)|.

Slider-crank (crank a, rod b, offset e, slider line y = e): dead centres at slider positions
s = sqrt((b +- a)^2 - e^2), crank angles asin(e / (b + a)) and pi + asin(e / (b - a)):
stroke = s_ext - s_fold, theta = |asin(e / (b - a)) - asin(e / (b + a))|.
"""

from __future__ import annotations

import numpy as np

from linkcli.errors import SchemaError


def _acos(x: float) -> float:
    return float(np.arccos(np.clip(x, -1.0, 1.0)))


def _ratio(theta: float) -> float:
    return (np.pi + theta) / (np.pi - theta)


def simulate_time_ratio_and_swing(a: float, b: float, c: float, d: float) -> tuple[float, float]:
    """(K, swing in radians) of the crank-rocker (a, b, c, d); SchemaError when it is not one
    (crank not the shortest link of a Grashof chain)."""
    links = sorted((a, b, c, d))
    if not (min(links) > 0 and a == links[0] and links[0] + links[3] < links[1] + links[2]):
        raise SchemaError("a Grashof crank-rocker (crank the shortest link)",
                          f"lengths {a:g}, {b:g}, {c:g}, {d:g}", key="linkage")
    ext, fold = b + a, b - a
    alpha_ext = _acos((d * d + ext * ext - c * c) / (2.0 * d * ext))
    alpha_fold = _acos((d * d + fold * fold - c * c) / (2.0 * d * fold))
    beta_ext = _acos((d * d + c * c - ext * ext) / (2.0 * d * c))
    beta_fold = _acos((d * d + c * c - fold * fold) / (2.0 * d * c))
    return float(_ratio(abs(alpha_fold - alpha_ext))), abs(beta_ext - beta_fold)


def simulate_stroke_and_time_ratio(a: float, b: float, e: float) -> tuple[float, float]:
    """(stroke, K) of the slider-crank (a, b, e); SchemaError unless the crank turns fully
    (a + |e| < b)."""
    if not (a > 0 and a + abs(e) < b):
        raise SchemaError("a slider-crank whose crank turns fully (input + |offset| < coupler)",
                          f"input {a:g}, coupler {b:g}, offset {e:g}", key="linkage")
    stroke = np.sqrt((b + a) ** 2 - e * e) - np.sqrt((b - a) ** 2 - e * e)
    theta = abs(np.arcsin(e / (b - a)) - np.arcsin(e / (b + a)))
    return float(stroke), float(_ratio(theta))
