"""Schema of `type = "linkage"`: a given four-bar to analyse."""

from __future__ import annotations

from linkcli.model import BRANCHES, FourBar, LinkageProblem, Meta
from linkcli.io.meta import MAX_LENGTH, MAX_RATIO, bounded_length, bounded_point, over_ratio
from linkcli.io.reader import Table

MAX_STEPS = 100_000
ASSEMBLY_RTOL = 1e-12  # relative: ranges that only touch close at one position and cannot move


def read_fourbar(t: Table, units) -> FourBar | None:
    """[linkage] with all four lengths, a branch, and optional placement."""
    lengths = {k: bounded_length(t, k) for k in ("ground", "input", "coupler", "output")}
    branch = t.string("branch", "open", choices=BRANCHES)
    cp = bounded_point(t, "coupler_point", None)
    gp = bounded_point(t, "ground_pivot", [0.0, 0.0])
    ga = t.number("ground_angle", 0.0, lo=-MAX_LENGTH, hi=MAX_LENGTH)
    if None in lengths.values() or branch is None or gp is None or ga is None:
        return None
    extremes = over_ratio(lengths)
    if extremes:
        longest, shortest = extremes
        t.error(longest, f"a linkage whose longest link is at most {MAX_RATIO:g} times its shortest "
                "(beyond, double precision cannot resolve its angles)",
                raw_got=f"{longest} = {lengths[longest]:g} and {shortest} = {lengths[shortest]:g}")
        return None
    a, b, c, d = (lengths[k] for k in ("input", "coupler", "output", "ground"))
    reach = min(d + a, b + c)  # |A B0| and the coupler with the output must overlap
    gap = reach - max(abs(d - a), abs(b - c))
    if gap <= ASSEMBLY_RTOL * reach:
        touch = ", which touch at one position only (a structure)" if gap > -ASSEMBLY_RTOL * reach else ""
        t.error(max(lengths, key=lengths.get), "a linkage that assembles over a range of input angles "
                "(|A B0|, from |ground - input| to ground + input, meeting |coupler - output| .. "
                "coupler + output)",
                raw_got=f"|A B0| in [{abs(d - a):g}, {d + a:g}] and coupler with output spanning "
                        f"[{abs(b - c):g}, {b + c:g}]{touch}")
        return None
    return FourBar(branch=branch, coupler_point=tuple(cp) if cp else None,
                   ground_pivot=tuple(gp), ground_angle=units.to_rad(ga), **lengths)


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
    fourbar = read_fourbar(link, meta.units) if link else None
    speed, steps = read_motion(root)
    if fourbar is None or speed is None or steps is None:
        return None
    return LinkageProblem(meta=meta, linkage=fourbar, input_speed=meta.units.to_rad(speed), steps=steps)
