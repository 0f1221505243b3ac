"""The slider-crank's `[linkage]` keys (docs/format.md): crank, rod, signed offset, a branch,
an optional coupler point. Pure Python (`check` reads it without numpy)."""

from __future__ import annotations

from linkcli.io.bounds import MAX_LENGTH, bounded_length, bounded_point
from linkcli.io.reader import Table
from linkcli.io.bounds import ASSEMBLY_RTOL, refuse_ratio
from linkcli.mechanisms.schema import drive_motion as read_motion  # noqa: F401 ([motion]: one drive)
from linkcli.model import BRANCHES, SliderCrank

KEYS = ("input", "coupler", "offset", "branch", "coupler_point")
JOINTS = ("A0", "A", "B", "guide")  # its pins and the slider's guide, as [joints] names them
LINKS = ("input", "coupler")  # its moving links, as [sections] names them (the strength section)
TOLERANCED = ("input", "coupler", "offset")  # [tolerance] lengths, table keys
PLAYS = {"clearance_slider": "the play of a slider in its guide"}  # [tolerance] keys of other plays
REPORTED_MOTION = ("slider_range", "stroke", "slow_stroke")  # its own output keys a result's [motion] may hold (sections.motion_section)
OUTPUT = "length"  # what its output is: an allowed_error is a slider position error (length)
MASSES = {"input": "input", "coupler": "coupler", "slider": "output"}  # [masses] key -> model.Masses field
POINT_MASSES = ("slider",)  # bodies that only translate: a mass, no centre or inertia
OUTPUT_LOAD = ("output_force", "N along the slider axis")  # its [loads] key on the output


def known_lengths(linkage) -> dict[str, float]:
    """Link -> length the tolerance checks compare against (the offset may be 0)."""
    return {"input": linkage.input, "coupler": linkage.coupler}


def read(t: Table, units) -> SliderCrank | None:
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
