"""Schema of `type = "linkage"`: a given four-bar, slider-crank or five-bar to analyse.

`[linkage] mechanism = "four-bar"` (the default), `"slider-crank"` (SPEC, "Slider-crank —
the second mechanism") or `"five-bar"`; `read_linkage` dispatches on it for linkage files,
precision-position files and result files alike, and the mechanism's `read_motion` reads
[motion] (one drive at a constant speed, or the five-bar's rows)."""

from __future__ import annotations

from linkcli.io.meta import MAX_LENGTH
from linkcli.io.reader import Table
from linkcli.io.loads import mechanism_of
from linkcli.mechanisms import module
from linkcli.mechanisms.schema import keys_mechanism, read_linkage
from linkcli.model import Meta

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
    from linkcli.model import LinkageProblem
    link = root.table("linkage", required=True)
    linkage = read_linkage(link, meta.units) if link else None
    named = mechanism_of(root)  # [motion] as the keys' mechanism's, when [linkage] holds another's
    study = module(keys_mechanism(link, named) or named, "schema").read_motion(root, meta, linkage)  # its [motion]
    if linkage is None or study is None:
        return None
    linkage, speed, steps = study
    return LinkageProblem(meta=meta, linkage=linkage, input_speed=speed, steps=steps)
