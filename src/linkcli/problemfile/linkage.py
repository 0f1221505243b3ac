"""Schema of `type = "linkage"`: a given four-bar to analyse."""

from __future__ import annotations

from linkcli.model import BRANCHES, FourBar, LinkageProblem, Meta
from linkcli.problemfile.reader import Table

DEFAULT_SECTIONS = ("lengths", "grashof", "transmission", "motion", "kinematics")
SECTIONS = ("lengths", "grashof", "transmission", "motion", "kinematics", "tolerance")
METHODS = ("auto",)
TOLERANCE = True
MAX_STEPS = 100_000


def read_fourbar(t: Table, units) -> FourBar | None:
    """[linkage] with all four lengths, a branch, and optional placement."""
    lengths = {k: t.number(k, positive=True, what="a positive length")
               for k in ("ground", "input", "coupler", "output")}
    branch = t.string("branch", "open", choices=BRANCHES)
    cp = t.number_list("coupler_point", None, length=2, what="coordinates [x, y]")
    gp = t.number_list("ground_pivot", [0.0, 0.0], length=2, what="coordinates [x, y]")
    ga = t.number("ground_angle", 0.0)
    if None in lengths.values() or branch is None or gp is None or ga is None:
        return None
    return FourBar(branch=branch, coupler_point=tuple(cp) if cp else None,
                   ground_pivot=tuple(gp), ground_angle=units.to_rad(ga), **lengths)


def parse(root: Table, meta: Meta) -> LinkageProblem | None:
    link = root.table("linkage", required=True)
    fourbar = read_fourbar(link, meta.units) if link else None
    mot = root.table("motion")
    speed, steps = 1.0, 360
    if mot is not None:
        speed = mot.number("input_speed", 1.0, what="a non-zero number (angle unit per second)")
        if speed == 0.0:
            mot.error("input_speed", "a non-zero number (angle unit per second)", 0.0)
            speed = None
        steps = mot.number("steps", 360, integer=True, lo=2, hi=MAX_STEPS)
    if fourbar is None or speed is None or steps is None:
        return None
    return LinkageProblem(meta=meta, linkage=fourbar, input_speed=meta.units.to_rad(speed), steps=steps)
