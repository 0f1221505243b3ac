"""The four-bar's `[linkage]` keys (docs/format.md): four lengths, a branch, an optional
coupler point and global placement. Pure Python (`check` reads it without numpy)."""

from __future__ import annotations

from linkcli.io.bounds import MAX_LENGTH, bounded_length, bounded_point
from linkcli.io.reader import Table
from linkcli.io.bounds import ASSEMBLY_RTOL, refuse_ratio
from linkcli.mechanisms.schema import drive_motion as read_motion  # noqa: F401 ([motion]: one drive)
from linkcli.model import BRANCHES, FourBar

KEYS = ("ground", "input", "coupler", "output", "branch", "coupler_point", "ground_pivot", "ground_angle")
JOINTS = ("A0", "A", "B", "B0")  # its pins, as [joints] names them
LINKS = ("input", "coupler", "output")  # its moving links, as [sections] names them (the strength section)
TOLERANCED = ("ground", "input", "coupler", "output")  # [tolerance] lengths, table keys
PLAYS: dict[str, str] = {}  # [tolerance] keys of other plays than the pins' clearance
REPORTED_MOTION: tuple[str, ...] = ()  # its own output keys a result's [motion] may hold
OUTPUT = "angle"  # what its output is: an allowed_error is an angle
MASSES = {"input": "input", "coupler": "coupler", "output": "output"}  # [masses] key -> model.Masses field
POINT_MASSES: tuple[str, ...] = ()  # bodies that only translate: a mass, no centre or inertia
OUTPUT_LOAD = ("output_torque", "N m on the output link")  # its [loads] key on the output


def known_lengths(linkage) -> dict[str, float]:
    """Link -> length the tolerance checks compare against."""
    return {k: getattr(linkage, k) for k in TOLERANCED}


def read(t: Table, units) -> FourBar | None:
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
