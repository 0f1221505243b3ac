"""Elementary functions from +, -, *, / and sqrt alone (numpy), for the atlas's bytes.

numpy picks its sin, cos, arctan2 and hypot kernels by CPU (AVX-512, AVX2 or baseline
loops, each rounding a little differently), and glibc picks FMA or plain variants of its
own; the basic operations and sqrt are correctly rounded by IEEE 754 on every CPU, in
every vector width. The atlas's curves are computed with these functions only, so that
`linkcli atlas build` writes the same bytes everywhere (checked with
NPY_DISABLE_CPU_FEATURES and OPENBLAS_CORETYPE in tests/atlas/test_atlas_store.py).

* `sincos(x)`: Cody-Waite reduction by pi/2 (fdlibm's two-part constant), then the
  Taylor series of sin to x^17 and cos to x^18 on |r| <= pi/4 (truncation below 1e-17).
* `atan2(y, x)`: t = min/max of |x|, |y| in [0, 1], halved twice by
  atan t = 2 atan(t / (1 + sqrt(1 + t^2))) to t <= tan(pi/16), the series to t^23
  (truncation below 1e-17), then the octant.
* `acos(c) = atan2(sqrt((1 - c)(1 + c)), c)`, `norm(x, y) = sqrt(x^2 + y^2)`.

Accurate to a few units in the last place; their value is that they are the same bits on
every machine, not that they are correctly rounded.
"""

from __future__ import annotations

import numpy as np

PIO2_HI = 1.57079632673412561417e+00  # pi/2 in two parts (fdlibm's pio2_1, pio2_1t)
PIO2_LO = 6.07710050650619224932e-11
PI = 3.14159265358979311600e+00
HALF_PI = 1.57079632679489655800e+00
TWO_OVER_PI = 6.36619772367581382433e-01
_SIN = tuple((-1.0) ** k / float(np.prod(np.arange(1, 2 * k + 2, dtype=float))) for k in range(1, 9))
_COS = tuple((-1.0) ** k / float(np.prod(np.arange(1, 2 * k + 1, dtype=float))) for k in range(1, 10))
_ATAN = tuple((-1.0) ** k / (2 * k + 1) for k in range(1, 12))


def _horner(r2: np.ndarray, coefficients) -> np.ndarray:
    acc = np.full_like(r2, coefficients[-1])
    for c in coefficients[-2::-1]:
        acc = acc * r2 + c
    return acc


def sincos(x) -> tuple[np.ndarray, np.ndarray]:
    """(sin x, cos x) for |x| up to about 1e6 (the reduction keeps ~1e-20 k there)."""
    x = np.asarray(x, dtype=float)
    k = np.rint(x * TWO_OVER_PI)
    r = (x - k * PIO2_HI) - k * PIO2_LO
    r2 = r * r
    s = r + (r * r2) * _horner(r2, _SIN)
    c = 1.0 + r2 * _horner(r2, _COS)
    q = np.mod(k, 4.0)
    sin = np.where(q == 0, s, np.where(q == 1, c, np.where(q == 2, -s, -c)))
    cos = np.where(q == 0, c, np.where(q == 1, -s, np.where(q == 2, -c, s)))
    return sin, cos


def atan2(y, x) -> np.ndarray:
    """The angle of (x, y) in [-pi, pi] (atan2(0, 0) = 0)."""
    y, x = np.broadcast_arrays(np.asarray(y, dtype=float), np.asarray(x, dtype=float))
    ax, ay = np.abs(x), np.abs(y)
    swap = ay > ax
    big = np.where(swap, ay, ax)
    t = np.where(swap, ax, ay) / np.where(big > 0.0, big, 1.0)
    for _ in range(2):
        t = t / (1.0 + np.sqrt(1.0 + t * t))
    t2 = t * t
    a = 4.0 * (t + (t * t2) * _horner(t2, _ATAN))
    a = np.where(swap, HALF_PI - a, a)
    a = np.where(x < 0.0, PI - a, a)
    return np.where(np.signbit(y), -a, a)


def acos(c) -> np.ndarray:
    c = np.clip(np.asarray(c, dtype=float), -1.0, 1.0)
    return atan2(np.sqrt((1.0 - c) * (1.0 + c)), c)


def norm(x, y) -> np.ndarray:
    """sqrt(x^2 + y^2) (numpy's hypot follows the CPU; values here are never near overflow)."""
    return np.sqrt(x * x + y * y)
