"""What a precision-position file decides before any solve, in pure Python (so that
`linkcli check` refuses what `synth` refuses, without importing numpy): the conditioning
of Freudenstein's system and, for three positions, whether its exact solution has finite
links and a real coupler.

Freudenstein's equation (Freudenstein 1955; Norton, Design of Machinery, sec. 5.14):
    K1 cos(psi) - K2 cos(phi) + K3 = cos(phi - psi),  K1 = d / a, K2 = d / c,
    K3 = (a^2 - b^2 + c^2 + d^2) / (2 a c),
one row [cos psi, -cos phi, 1] per position. Its 2-norm condition number is the ratio of
the largest to the smallest singular value, found here by one-sided Jacobi rotations
(Hestenes 1958), which keep the small singular values to full relative accuracy.
"""

from __future__ import annotations

import math

ILL_CONDITIONED = 1e12  # 2-norm condition number above which the system is singular
FINITE_RATIO = 1e-12  # |K1| or |K2| at or below: an infinite link (starts.lengths_of)
JACOBI_SWEEPS = 60


def freudenstein_rows(phi, psi) -> list[list[float]]:
    """Rows [cos psi, -cos phi, 1] (angles in rad)."""
    return [[math.cos(q), -math.cos(p), 1.0] for p, q in zip(phi, psi)]


def condition_number(rows: list[list[float]]) -> float:
    """sigma_max / sigma_min of an n x 3 matrix (inf when a singular value is 0)."""
    cols = [[r[j] for r in rows] for j in range(3)]
    for _ in range(JACOBI_SWEEPS):
        rotated = False
        for i in range(2):
            for j in range(i + 1, 3):
                u, v = cols[i], cols[j]
                alpha = math.fsum(x * x for x in u)
                beta = math.fsum(y * y for y in v)
                gamma = math.fsum(x * y for x, y in zip(u, v))
                if gamma == 0.0 or abs(gamma) <= 1e-15 * math.sqrt(alpha * beta):
                    continue
                rotated = True
                zeta = (beta - alpha) / (2.0 * gamma)
                t = math.copysign(1.0, zeta) / (abs(zeta) + math.sqrt(1.0 + zeta * zeta))
                c = 1.0 / math.sqrt(1.0 + t * t)
                s = c * t
                cols[i] = [c * x - s * y for x, y in zip(u, v)]
                cols[j] = [s * x + c * y for x, y in zip(u, v)]
        if not rotated:
            break
    sigma = [math.sqrt(math.fsum(x * x for x in col)) for col in cols]
    return math.inf if min(sigma) == 0.0 else max(sigma) / min(sigma)


def exact_ratios(rows: list[list[float]], rhs: list[float]) -> list[float]:
    """K1, K2, K3 of three positions by Cramer's rule (the system is well conditioned)."""
    def det(m):
        return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
                - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
    whole = det(rows)
    out = []
    for j in range(3):
        m = [[rhs[i] if k == j else rows[i][k] for k in range(3)] for i in range(3)]
        out.append(det(m) / whole)
    return out


def position_problem(phi, psi, ground: float) -> tuple[str, str] | None:
    """(expected, found) of the first reason the positions determine no linkage, or None:
    a singular system (any number of positions); for three positions, an infinite link or
    a coupler that is not real. The words are those of the solver's own checks."""
    n = len(phi)
    names = ", ".join(str(i + 1) for i in range(n))
    rows = freudenstein_rows(phi, psi)
    if condition_number(rows) > ILL_CONDITIONED:
        return ("positions that determine a linkage (Freudenstein's system is singular)",
                f"positions {names} give a singular system")
    if n != 3:
        return None
    k1, k2, k3 = exact_ratios(rows, [math.cos(p - q) for p, q in zip(phi, psi)])
    if abs(k1) <= FINITE_RATIO or abs(k2) <= FINITE_RATIO:
        return ("positions that determine finite input and output links",
                f"positions {names} give an infinite link")
    a, c, d = ground / k1, ground / k2, ground
    b2 = a * a + c * c + d * d - 2 * a * c * k3
    if b2 <= 0:
        return ("positions that a real coupler can join", f"positions {names} need coupler^2 = {b2:.6g} <= 0")
    return None
