"""Start dyads for many poses from the centre-point curve of four of them.

A dyad (ground pivot G, moving pivot M in the body frame) guides the body through pose i
when its moving pivot there, A_i = p_i + R(theta_i) M, lies on the circle about G:
|A_i - G| = r for every i. Four poses leave a one-parameter family of such dyads, the
centre-point curve (burmester.centre_point_curve; Sandor & Erdman, Advanced Mechanism
Design vol. 2, sec. 3.3); along it the dyad fits the other poses well or badly. Scored on
all n poses by the spread of the radii,

    e(G, M) = sqrt(mean_i (|A_i - G| - mean_j |A_j - G|)^2) / L   (L: the poses'
    characteristic length),

the best few distinct dyads of the curve stand in for the Burmester dyads of a five-pose
subset (which fit five poses exactly): the least-squares search uses them once the
five-pose subsets run out (six or seven poses leave 6 or 21 of them: a round takes up to
13), so that each later round still starts from linkages made for these poses, from
subsets no earlier round took. The curve is drawn as a pencil of lines through the pole of
the two poses that turn the body most (|sin(dtheta / 2)| largest): the pole of a small turn
lies far away, and few of its lines cut the curve near the poses.
"""

from __future__ import annotations

import numpy as np

from linkcli.noise import NOISE_FLOOR

from .burmester import centre_point_curve
from .poses import characteristic_length, to_global

SAMPLES = 181  # directions sampled on the curve (two cuts each)
DISTINCT = 0.05  # characteristic lengths between the ground pivots of two dyads kept


def fitting_dyads(poses, subset, count: int):
    """The `count` distinct dyads of the centre-point curve of the four poses `subset`
    that fit all `poses` best (module docstring): (G (K, 2), M (K, 2)), K <= count, best
    first; none when the four poses only translate the body (no finite pole)."""
    sub = np.asarray(subset, int)
    turns = np.abs(np.sin(0.5 * (poses[sub, 2][:, None] - poses[sub, 2][None, :])))  # |sin(dtheta / 2)|
    i, j = np.unravel_index(np.argmax(np.triu(turns, 1)), turns.shape)  # the first largest
    if 2.0 * turns[i, j] <= NOISE_FLOOR:  # a translation: no finite pole
        return np.zeros((0, 2)), np.zeros((0, 2))
    order = [i, j] + [k for k in range(4) if k not in (i, j)]
    ground, moving = centre_point_curve(poses[sub[order]], samples=SAMPLES).pairs()
    if not len(ground):
        return ground, moving
    scale = characteristic_length(poses)
    radius = np.linalg.norm(to_global(poses, moving[:, None, :]) - ground[:, None, :], axis=-1)  # (K, n)
    spread = np.sqrt(np.mean((radius - radius.mean(1, keepdims=True)) ** 2, 1)) / scale
    kept: list[int] = []
    for k in np.argsort(spread, kind="stable"):  # a short loop: it stops at `count` kept
        if not np.isfinite(spread[k]):
            break
        if all(np.hypot(*(ground[k] - ground[j])) > DISTINCT * scale for j in kept):
            kept.append(int(k))
            if len(kept) == count:
                break
    return ground[kept], moving[kept]
