"""Why exact motion generation found no candidate linkage, in words for the message.

A crank dyad guides a body point M on a circle about its ground pivot G, so the n
positions of M must be concyclic. Exact synthesis finds no pair of dyads when:

- the poses are a pure translation (one angle): every body point's positions are the
  pose origins shifted by a fixed vector, so they are concyclic only if the origins are;
  origins on a line leave no circle at all (a slider would guide the body), and every pole
  is at infinity, so the pole-based constructions have nothing to start from;
- five poses have fewer than two real Burmester dyads (the intersections of the
  centre-point curves C1234 and C1235 that solve all five poses come in 0, 2 or 4; the
  elimination in burmester.py finds every real one, so 0 is a proof, not a miss);
- four poses whose centre-point curve has no finite point within reach;
- three poses: no sampled ground pivot within the bounds has a moving pivot.

Numbers go through textnum.num (rounded in every output like any other).
"""

from __future__ import annotations

import numpy as np

from linkcli.noise import NOISE_FLOOR
from linkcli.textnum import num

from .poses import characteristic_length


def _wrapped(angle):
    return (np.asarray(angle, float) + np.pi) % (2.0 * np.pi) - np.pi


def is_translation(poses) -> bool:
    """Every pose at one angle (within the noise floor, in rad)."""
    return bool(np.all(np.abs(_wrapped(poses[:, 2] - poses[0, 2])) <= NOISE_FLOOR))


def rotating_pair(poses) -> tuple[int, int] | None:
    """The first pair of poses (i < j, in order) that turns the body: its pole is finite;
    None for a pure translation."""
    n = len(poses)
    for i in range(n):
        for j in range(i + 1, n):
            if abs(_wrapped(poses[j, 2] - poses[i, 2])) > NOISE_FLOOR:
                return i, j
    return None


def _collinear(points, scale: float) -> bool:
    """The points lie on one line, within the noise floor of `scale`."""
    centred = points - points.mean(0)
    return bool(np.linalg.svd(centred, compute_uv=False)[-1] <= NOISE_FLOOR * scale * np.sqrt(len(points)))


def translation_reason(poses, units) -> str | None:
    """Why a pure translation admits no crank dyad here, or None if the poses turn."""
    if not is_translation(poses):
        return None
    angle = f"{num(float(units.from_rad(float(_wrapped(poses[0, 2])))))} {units.angle}"
    n = len(poses)
    if _collinear(poses[:, :2], characteristic_length(poses)):
        return (f"the {n} poses are a pure translation along a straight line (every pose at {angle}): each "
                f"point of the body moves on a straight line, and no crank's circle passes through {n} "
                "points of a line (a slider would guide the body)")
    return (f"the {n} poses are a pure translation (every pose at {angle}): every pole is at infinity, and "
            "each point of the body passes through the pose origins shifted by one vector, on a common "
            "circle only where the origins are (a parallelogram guides such a body): give the poses a "
            "rotation")


def burmester_reason(real_dyads: int) -> str:
    """Five poses with fewer than two real Burmester dyads."""
    which = "no real Burmester dyad" if real_dyads == 0 else "only 1 real Burmester dyad"
    return (f"the 5 poses have {which} (a four-bar needs two; they come in 0, 2 or 4, and every "
            "real one is found: the other intersections of the centre-point curves C1234 and C1235 "
            "are complex); move a pose, or leave one out (four poses give a one-parameter family)")


def curve_reason() -> str:
    """Four poses whose centre-point curve has no finite point within reach."""
    return ("the centre-point curve of the four poses has no point with a finite moving pivot within "
            "10 characteristic lengths of the poses")


def search_reason(count: int) -> str:
    """Three poses: none of the sampled ground pivots has a moving pivot by inversion."""
    return (f"none of the {count} ground pivot pairs drawn within the bounds has moving pivots for the three "
            "poses (each lies on the circle through the poles)")
