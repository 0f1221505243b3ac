"""Worst transmission angle over the full crank turn, in closed form (radians).

Four-bar (crank a, coupler b, rocker c, ground d): the cosine rule in the triangle A B B0 with
f = |A B0|, f^2 = a^2 + d^2 - 2 a d cos(phi), gives cos(mu) = (b^2 + c^2 - f^2) / (2 b c).
f is extreme at phi = 0 (f = d - a) and phi = pi (f = d + a) and mu is monotone in f, so over a
full turn mu runs between mu(d - a) and mu(d + a): the worst deviation from 90 deg is
min(mu0, pi - mu0, mu180, pi - mu180). mu is evaluated as atan2 of Heron's factored sine,
    sin(mu) 2 b c = sqrt((f - b + c) (f + b - c) (b + c - f) (b + c + f)),
which keeps full relative precision near mu = 0 or pi (no arccos of a number near 1).

Slider-crank (crank a, rod b, offset e): cos(mu) = |a sin(phi) - e| / b, worst where
|a sin(phi) - e| = a + |e|: mu_min = atan2(sqrt((b - a - |e|) (b + a + |e|)), a + |e|);
best mu_max = pi/2 when a >= |e|, else mu at |e| - a.
"""

from __future__ import annotations

import numpy as np


def coupler_rocker_angle(b, c, f):
    """Transmission angle mu in [0, pi] for coupler b, rocker c, |A B0| = f (vectorized)."""
    prod = (f - b + c) * (f + b - c) * (b + c - f) * (b + c + f)
    return np.arctan2(np.sqrt(np.clip(prod, 0.0, None)), b * b + c * c - f * f)


def four_bar_extremes(a, b, c, d):
    """(mu at phi = 0, mu at phi = pi): the two extremes over a full crank turn."""
    return coupler_rocker_angle(b, c, d - a), coupler_rocker_angle(b, c, d + a)


def four_bar_margins(a, b, c, d, window=(0.0, np.pi)):
    """Stacked margins (mu0 - lo, mu180 - lo, hi - mu0, hi - mu180): their min is how far the
    whole turn stays inside the window (the worst transmission angle for (0, pi))."""
    lo, hi = window
    mu0, mu180 = four_bar_extremes(a, b, c, d)
    return np.stack(np.broadcast_arrays(mu0 - lo, mu180 - lo, hi - mu0, hi - mu180))


def four_bar_worst(a, b, c, d):
    """Worst transmission angle over the full turn: min(mu, pi - mu) at its extremes."""
    return np.min(four_bar_margins(a, b, c, d), axis=0)


def slider_extremes(a, b, e):
    """(mu_min, mu_max) of a slider-crank over the full turn."""
    e = np.abs(e)
    s = a + e
    mu_min = np.arctan2(np.sqrt(np.clip((b - s) * (b + s), 0.0, None)), s)
    low = np.clip(e - a, 0.0, None)
    mu_max = np.arctan2(np.sqrt(np.clip((b - low) * (b + low), 0.0, None)), low)
    return mu_min, mu_max


def slider_margins(a, b, e, window=(0.0, np.pi)):
    """Stacked margins (mu_min - lo, hi - mu_max) of a slider-crank (see four_bar_margins)."""
    lo, hi = window
    mu_min, mu_max = slider_extremes(a, b, e)
    return np.stack(np.broadcast_arrays(mu_min - lo, hi - mu_max))
