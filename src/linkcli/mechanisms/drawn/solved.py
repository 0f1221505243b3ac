"""A drawing solved once: its structure and plan (structure), the plan run over rows (solver,
groups), the leading drive's reach (motion) and every drive's drawn value. Cached per drawing
(`solved`): the home, its sections, loads, made parts, plots and dynamics all start here.

A turning drive's value is the angle of the line from its ground pivot to the link's first
other joint (global frame); a sliding drive's, the slider's place along its guide, (J - O) . u
with O the guide body's frame origin (the global origin for a ground guide) and u the guide's
direction.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from linkcli.mechanisms.drawn.model import TURN, Drawn

TWO_PI = 2.0 * math.pi


@dataclass
class Solved:
    """A drawing's structure, its plan over rows, and the leading drive's reach and frame."""

    drawing: Drawn
    structure: object
    kin: object
    reach: object
    start: float  # the leading drive's drawn value (rad or length)
    turning: bool
    starts: tuple[float, ...]  # every drive's drawn value

    def q_of(self, x, full_turn: bool) -> np.ndarray:
        """Offsets from the drawing of leading-drive values x (full turn: into [0, 2 pi))."""
        q = np.asarray(x, dtype=float) - self.start
        return np.mod(q, TWO_PI) if full_turn else q

    def value(self, q) -> np.ndarray:
        return self.start + np.asarray(q, dtype=float)


@lru_cache(maxsize=16)
def solved(drawing: Drawn) -> Solved:
    from linkcli.mechanisms.drawn import motion
    from linkcli.mechanisms.drawn.solver import Kinematics
    from linkcli.mechanisms.drawn.structure import analyse
    structure = analyse(drawing)
    kin = Kinematics(drawing, structure)
    starts = tuple(drive_start(drawing, kin.geometry, drive) for drive in drawing.drives)
    return Solved(drawing, structure, kin, motion.reach(kin), starts[0], drawing.drives[0].kind == TURN, starts)


def drive_start(drawing: Drawn, geo, drive) -> float:
    """A drive's drawn value: a turning link's angle from its ground pivot to its first other
    joint; a slider's place (J - O) . u along its guide (module docstring)."""
    if drive.kind == TURN:
        link = drawing.link(drive.name)
        pivot = next(j for j in link.joints if drawing.joint(j).ground)
        other = next(j for j in link.joints if j != pivot)
        (px, py), (ox, oy) = drawing.joint(pivot).at, drawing.joint(other).at
        return math.atan2(oy - py, ox - px)
    body, _, beta = geo.guides[drive.name]
    angle = beta + geo.angle0[body]
    return float(np.dot(np.asarray(drawing.joint(drive.name).at) - geo.origin0[body],
                        [math.cos(angle), math.sin(angle)]))
