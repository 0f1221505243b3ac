"""Schema of `type = "linkage"`: a given four-bar or slider-crank to analyse.

`[linkage] mechanism = "four-bar"` (the default) or `"slider-crank"` (SPEC, "Slider-crank —
the second mechanism"); `read_linkage` dispatches on it for linkage files, precision-position
files and result files alike."""

from __future__ import annotations

from linkcli.io.meta import MAX_LENGTH
from linkcli.io.reader import Table
from linkcli.mechanisms.schema import read_linkage
from linkcli.model import LinkageProblem, Meta

MAX_STEPS = 100_000


def read_motion(root: Table) -> tuple[float | None, int | None]:
    """[motion] of a kinematics study: input_speed (angle unit per second, non-zero,
    default 1) and steps (2 .. MAX_STEPS, default 360); None for a value in error."""
    mot = root.table("motion")
    speed, steps = 1.0, 360
    if mot is not None:
        speed = mot.number("input_speed", 1.0, lo=-MAX_LENGTH, hi=MAX_LENGTH,
                           what="a non-zero number (angle unit per second)")
        if speed == 0.0:
            mot.error("input_speed", "a non-zero number (angle unit per second)", 0.0)
            speed = None
        steps = mot.number("steps", 360, integer=True, lo=2, hi=MAX_STEPS)
    return speed, steps


def parse(root: Table, meta: Meta) -> LinkageProblem | None:
    link = root.table("linkage", required=True)
    fourbar = read_linkage(link, meta.units) if link else None
    speed, steps = read_motion(root)
    if fourbar is None or speed is None or steps is None:
        return None
    return LinkageProblem(meta=meta, linkage=fourbar, input_speed=meta.units.to_rad(speed), steps=steps)
