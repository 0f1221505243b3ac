"""The one wrap: angle positions in (-pi, pi], the same for every mechanism and report."""

from __future__ import annotations

import numpy as np

TWO_PI = 2.0 * np.pi
WRAP_SNAP = 1e-12  # rad: an angle within round-off of -pi is taken as +pi


def wrap(angle):
    """Angles in (-pi, pi]; one within WRAP_SNAP of -pi (round-off of a position at
    180 deg) becomes +pi, so that a report never alternates between -180 and 180."""
    out = np.mod(np.asarray(angle, dtype=float) + np.pi, TWO_PI) - np.pi
    return np.where(out <= -np.pi + WRAP_SNAP, out + TWO_PI, out)
