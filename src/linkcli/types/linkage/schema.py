"""Schema of `type = "linkage"`: a given four-bar or slider-crank to analyse.

`[linkage] mechanism = "four-bar"` (the default) or `"slider-crank"` (SPEC, "Slider-crank —
the second mechanism"); `read_linkage` dispatches on it for linkage files, precision-position
files and result files alike."""

from __future__ import annotations

from linkcli.model import BRANCHES, FourBar, LinkageProblem, Meta, SliderCrank
from linkcli.io.meta import MAX_LENGTH, MAX_RATIO, bounded_length, bounded_point, over_ratio
from linkcli.io.reader import Table, describe

MAX_STEPS = 100_000
ASSEMBLY_RTOL = 1e-12  # relative: ranges that only touch close at one position and cannot move


MECHANISMS = ("four-bar", "slider-crank")
FOUR_BAR_ONLY = ("ground", "output", "ground_pivot", "ground_angle")
SLIDER_ONLY = ("offset",)


def refuse_ratio(t, lengths: dict) -> bool:
    """A located error (and True) when the longest link is over MAX_RATIO times the shortest:
    beyond, double precision cannot resolve the linkage's angles."""
    extremes = over_ratio(lengths)
    if not extremes:
        return False
    longest, shortest = extremes
    t.error(longest, f"a linkage whose longest link is at most {MAX_RATIO:g} times its shortest "
            "(beyond, double precision cannot resolve its angles)",
            raw_got=f"{longest} = {lengths[longest]:g} and {shortest} = {lengths[shortest]:g}")
    return True


def read_mechanism(t: Table) -> str | None:
    """`mechanism`: one of MECHANISMS, default four-bar; None when bad (error recorded)."""
    return t.string("mechanism", "four-bar", choices=MECHANISMS)


def refuse_foreign(t: Table, mechanism: str) -> bool:
    """Keys of the other mechanism in this [linkage]: one located error each; True if any."""
    foreign = SLIDER_ONLY if mechanism == "four-bar" else FOUR_BAR_ONLY
    own = ("ground, input, coupler, output, branch, coupler_point, ground_pivot, ground_angle"
           if mechanism == "four-bar" else "input, coupler, offset, branch, coupler_point")
    found = False
    for key in foreign:
        if key in t:
            t.allow(key)  # one message, not a second "unknown key" for the same line
            t.error(key, f"no {key} in a {mechanism} [linkage] (its keys: {own})",
                    raw_got=f"{key} = {describe(t.data[key])}")
            found = True
    return found


def read_slider_crank(t: Table, units):
    """[linkage] of a slider-crank: input (crank a), coupler (rod b), signed offset e, branch,
    optional coupler_point. It must assemble over a range of crank angles: |e| < a + b
    (|e - a sin(phi)| <= b for some phi; at |e| = a + b only at one angle, a structure)."""
    lengths = {k: bounded_length(t, k) for k in ("input", "coupler")}
    offset = t.number("offset", lo=-MAX_LENGTH, hi=MAX_LENGTH, what="a signed length (the slider axis at y = offset)")
    branch = t.string("branch", "open", choices=BRANCHES)
    cp = bounded_point(t, "coupler_point", None)
    if None in lengths.values() or offset is None or branch is None:
        return None
    if refuse_ratio(t, lengths):
        return None
    a, b = lengths["input"], lengths["coupler"]
    reach = a + b
    if abs(offset) >= reach * (1 - ASSEMBLY_RTOL):
        touch = ", which reaches the slider axis at one crank angle only (a structure)" \
            if abs(offset) <= reach * (1 + ASSEMBLY_RTOL) else ""
        t.error("offset", "a slider axis the crank and coupler can reach over a range of crank angles "
                "(|offset| < input + coupler)",
                raw_got=f"|offset| = {abs(offset):g} and input + coupler = {reach:g}{touch}")
        return None
    return SliderCrank(input=a, coupler=b, offset=offset, branch=branch,
                       coupler_point=tuple(cp) if cp else None)


def read_linkage(t: Table, units):
    """[linkage] of either mechanism: a FourBar or a SliderCrank; None when in error."""
    mechanism = read_mechanism(t)
    if mechanism is None:  # one line for the mechanism, none for keys that depend on it
        t.allow("ground", "input", "coupler", "output", "offset", "branch", "coupler_point",
                "ground_pivot", "ground_angle")
        return None
    foreign = refuse_foreign(t, mechanism)
    linkage = read_slider_crank(t, units) if mechanism == "slider-crank" else read_fourbar(t, units)
    return None if foreign else linkage


def read_fourbar(t: Table, units) -> FourBar | None:
    """[linkage] with all four lengths, a branch, and optional placement."""
    lengths = {k: bounded_length(t, k) for k in ("ground", "input", "coupler", "output")}
    branch = t.string("branch", "open", choices=BRANCHES)
    cp = bounded_point(t, "coupler_point", None)
    gp = bounded_point(t, "ground_pivot", [0.0, 0.0])
    ga = t.number("ground_angle", 0.0, lo=-MAX_LENGTH, hi=MAX_LENGTH)
    if None in lengths.values() or branch is None or gp is None or ga is None:
        return None
    if refuse_ratio(t, lengths):
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
    fourbar = read_linkage(link, meta.units) if link else None
    speed, steps = read_motion(root)
    if fourbar is None or speed is None or steps is None:
        return None
    return LinkageProblem(meta=meta, linkage=fourbar, input_speed=meta.units.to_rad(speed), steps=steps)
