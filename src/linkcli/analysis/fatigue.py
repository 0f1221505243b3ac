"""Safety factors of a stress cycle: fatigue criteria, static yield, shear conversion and the
pinned-pinned column (docs/strength.md). Stresses and strengths in one unit (MPa); arrays
broadcast. An unloaded part has an infinite factor.

Source: Budynas & Nisbett, *Shigley's Mechanical Engineering Design* (9th ed.): "fatigue
failure criteria for fluctuating stress" (Soderberg, modified Goodman, Gerber, ASME-elliptic);
a compressive (or zero) mean stress leaves the fatigue factor Se / sigma_a (the designer's
fatigue diagram is flat for sigma_m <= 0); "combinations of loading modes": alternating and
mean components each as von Mises stresses, sigma' = sqrt(3) tau for shear, i.e. shear
strengths 0.577 times the tensile ones; "long columns" (Euler) and "intermediate-length columns
with central loading" (Johnson), end-condition constant C = 1.
"""

from __future__ import annotations

import math

import numpy as np

CRITERIA = ("goodman", "gerber", "soderberg", "asme-elliptic")
VON_MISES_SHEAR = math.sqrt(3.0)  # sigma' = sqrt(3) tau (pure shear); 1 / sqrt(3) = 0.577


def cycle(history, axis: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """(alternating, mean) of a stress history along `axis`: (max - min) / 2 and
    (max + min) / 2 of the cycle (Shigley, "characterizing fluctuating stresses"), not the
    time average."""
    high, low = np.max(history, axis=axis), np.min(history, axis=axis)
    return (high - low) / 2.0, (high + low) / 2.0


def fatigue_factor(alternating, mean, endurance: float, ultimate: float, yield_: float,
                   criterion: str = "goodman") -> np.ndarray:
    """The fatigue safety factor n of (sigma_a, sigma_m) on the criterion's line:

        goodman        1/n = sigma_a/Se + sigma_m/Sut
        soderberg      1/n = sigma_a/Se + sigma_m/Sy
        gerber         n sigma_a/Se + (n sigma_m/Sut)^2 = 1
                       n = 2 Se / (sigma_a + sqrt(sigma_a^2 + (2 sigma_m Se / Sut)^2))
        asme-elliptic  (n sigma_a/Se)^2 + (n sigma_m/Sy)^2 = 1

    (the Gerber root in a form without cancellation); sigma_m <= 0: n = Se / sigma_a."""
    a = np.asarray(alternating, dtype=float)
    m = np.asarray(mean, dtype=float)
    tension = np.maximum(m, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        if criterion == "goodman":
            inverse = a / endurance + tension / ultimate
        elif criterion == "soderberg":
            inverse = a / endurance + tension / yield_
        elif criterion == "gerber":
            inverse = (a + np.sqrt(a * a + (2.0 * tension * endurance / ultimate) ** 2)) / (2.0 * endurance)
        elif criterion == "asme-elliptic":
            inverse = np.hypot(a / endurance, tension / yield_)
        else:
            raise ValueError(f"unknown fatigue criterion {criterion!r}")
        return np.where(inverse > 0, 1.0 / np.where(inverse > 0, inverse, 1.0), np.inf)


def static_factor(peak, strength: float) -> np.ndarray:
    """strength / |peak| (infinite when the peak is 0)."""
    peak = np.abs(np.asarray(peak, dtype=float))
    with np.errstate(divide="ignore"):
        return np.where(peak > 0, strength / np.where(peak > 0, peak, 1.0), np.inf)


def column_load(length: float, area: float, inertia: float, modulus: float,
                yield_: float) -> tuple[float, str]:
    """(critical load, "euler" or "johnson") of a pinned-pinned column (C = 1), SI or any
    consistent units: slenderness l/k, k = sqrt(I/A); beyond (l/k)_1 = sqrt(2 pi^2 E / Sy)
    Euler's P = pi^2 E I / l^2, below it Johnson's parabola P = A (Sy - (Sy l / (2 pi k))^2 / E)."""
    k = math.sqrt(inertia / area)
    slender = length / k
    if slender >= math.sqrt(2.0 * math.pi ** 2 * modulus / yield_):
        return math.pi ** 2 * modulus * inertia / length ** 2, "euler"
    return area * (yield_ - (yield_ * slender / (2.0 * math.pi)) ** 2 / modulus), "johnson"
