"""The slider-crank's `[linkage]` keys (docs/format.md): crank, rod, signed offset, a branch,
an optional coupler point. Pure Python (`check` reads it without numpy)."""

from __future__ import annotations

from linkcli.io.bounds import ASSEMBLY_RTOL, MAX_LENGTH, bounded_length, bounded_point, refuse_ratio
from linkcli.io.reader import Table
from linkcli.mechanisms.schema import ForceParts, Schema, coupler_point_headings, has_coupler_point
from linkcli.mechanisms.slider_crank.model import BRANCHES, SliderCrank

CARRIED = {"A0": ("ground", "input"), "A": ("input", "coupler"), "B": ("coupler", "slider")}  # each pin -> the bodies it joins


class SliderCrankSchema(Schema):
    """The slider-crank's vocabulary (mechanisms.schema.Schema): `guide` is the slider's guide
    among its pins; the slider's play in its guide is a play of its own; the slider is a
    point mass; its output is a slider position (a length)."""

    name = "slider-crank"
    keys = ("input", "coupler", "offset", "branch", "coupler_point")
    joints = ("A0", "A", "B", "guide")
    links = ("input", "coupler")
    toleranced = ("input", "coupler", "offset")
    plays = {"clearance_slider": "the play of a slider in its guide"}
    reported_motion = ("slider_range", "stroke", "slow_stroke")  # sections.motion_section
    output = "length"
    masses = {"input": "input", "coupler": "coupler", "slider": "output"}
    point_masses = ("slider",)
    output_load = ("output_force", "N along the slider axis")
    class_keys = ("class", "crank_plus_offset", "coupler")

    def read(self, t: Table, units) -> SliderCrank | None:
        return _read(t, units)

    def known_lengths(self, linkage) -> dict[str, float]:
        """Link -> length the tolerance checks compare against (the offset may be 0)."""
        return {"input": linkage.input, "coupler": linkage.coupler}

    def class_block(self, g: dict, fmt) -> tuple[str, list[tuple[str, object]]]:
        """("Class", rows): the class and the test a + |e| <= b that decides it."""
        a_e, b = g["crank_plus_offset"], g["coupler"]
        rel = "<" if a_e < b else ("=" if a_e == b else ">")
        return "Class", [("class", g["class"]), ("input + |offset| vs coupler", f"{fmt(a_e)} {rel} {fmt(b)}")]

    def kinematics_headings(self, rows, length, angle) -> dict[str, str]:
        return {"input": f"input ({angle})", "coupler": f"coupler ({angle})", "transmission": f"mu ({angle})",
                "coupler_velocity": f"w coupler ({angle}/s)", "coupler_acceleration": f"a coupler ({angle}/s2)",
                "slider": f"slider ({length})", "slider_velocity": f"v slider ({length}/s)",
                "slider_acceleration": f"a slider ({length}/s2)", **coupler_point_headings(length)}

    def motion_units(self, length, angle) -> dict[str, str]:
        return {"input_range": angle, "slider_range": length, "stroke": length, "input_speed": f"{angle}/s"}

    def force_parts(self, root: Table, kind: str) -> ForceParts:
        """Joints A0, A, B (the slider pin; and the coupler point P when the linkage has one);
        turning links input and coupler (the slider only translates); pins A0, A, B (the guide
        is no pin: its friction needs no diameter)."""
        points = dict(CARRIED)
        if has_coupler_point(root, kind):
            points["P"] = ("coupler",)
        return ForceParts(points=points, links=("input", "coupler"), pins=tuple(CARRIED))


def _read(t: Table, units) -> SliderCrank | None:
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


SCHEMA = SliderCrankSchema()
