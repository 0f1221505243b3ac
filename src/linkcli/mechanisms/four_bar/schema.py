"""The four-bar's `[linkage]` keys (docs/format.md): four lengths, a branch, an optional
coupler point and global placement. Pure Python (`check` reads it without numpy)."""

from __future__ import annotations

from linkcli.io.bounds import ASSEMBLY_RTOL, MAX_LENGTH, bounded_length, bounded_point, refuse_ratio
from linkcli.io.reader import Table
from linkcli.mechanisms.four_bar.model import BRANCHES, FourBar
from linkcli.mechanisms.schema import ForceParts, Schema, coupler_point_headings, has_coupler_point

CARRIED = {"A0": ("ground", "input"), "A": ("input", "coupler"), "B": ("coupler", "output"),
           "B0": ("ground", "output")}  # each pin -> the bodies it joins (force elements, friction)


class FourBarSchema(Schema):
    """The four-bar's vocabulary (mechanisms.schema.Schema)."""

    name = "four-bar"
    keys = ("ground", "input", "coupler", "output", "branch", "coupler_point", "ground_pivot", "ground_angle")
    joints = ("A0", "A", "B", "B0")
    links = ("input", "coupler", "output")
    toleranced = ("ground", "input", "coupler", "output")
    output = "angle"
    masses = {"input": "input", "coupler": "coupler", "output": "output"}
    output_load = ("output_torque", "N m on the output link")
    class_keys = ("class", "shortest", "longest", "s_plus_l", "p_plus_q")

    def read(self, t: Table, units) -> FourBar | None:
        return _read(t, units)

    def class_block(self, g: dict, fmt) -> tuple[str, list[tuple[str, object]]]:
        """("Grashof", rows): the class, the shortest and longest link, s + l against p + q."""
        sl, pq = g["s_plus_l"], g["p_plus_q"]
        rel = "vs" if sl is None or pq is None else "<" if sl < pq else ("=" if sl == pq else ">")
        return "Grashof", [("class", g["class"]), ("shortest", g["shortest"]), ("longest", g["longest"]),
                           ("s + l vs p + q", f"{fmt(sl)} {rel} {fmt(pq)}")]

    def kinematics_headings(self, rows, length, angle) -> dict[str, str]:
        return {"input": f"input ({angle})", "coupler": f"coupler ({angle})", "output": f"output ({angle})",
                "transmission": f"mu ({angle})", "coupler_velocity": f"w coupler ({angle}/s)",
                "output_velocity": f"w output ({angle}/s)", "coupler_acceleration": f"a coupler ({angle}/s2)",
                "output_acceleration": f"a output ({angle}/s2)", **coupler_point_headings(length)}

    def motion_units(self, length, angle) -> dict[str, str]:
        return {"input_range": angle, "output_range": angle, "output_swing": angle, "input_speed": f"{angle}/s"}

    def force_parts(self, root: Table, kind: str) -> ForceParts:
        """Joints A0, A, B, B0 (and the coupler point P when the linkage has one); links input,
        coupler, output; pins A0, A, B, B0; counterweights on input and output (Berkof-Lowen)."""
        points = dict(CARRIED)
        if has_coupler_point(root, kind):
            points["P"] = ("coupler",)
        return ForceParts(points=points, links=("input", "coupler", "output"), pins=tuple(CARRIED),
                          counterweighted=("input", "output"))


def _read(t: Table, units) -> FourBar | None:
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


SCHEMA = FourBarSchema()
