"""Schema of `type = "precision-position"` (Freudenstein function generation)."""

from __future__ import annotations

import math

from linkcli.model import Meta, PrecisionPositionProblem
from linkcli.reading.meta import in_motion_order
from linkcli.io.bounds import MAX_LENGTH, bounded_length
from linkcli.errors import SchemaError
from linkcli.io.reader import Table
from linkcli.types.precision_position.system import position_problem
from linkcli.types.precision_position.slider_system import slider_position_problem
from linkcli.reading.linkage import read_mechanism, refuse_foreign
from linkcli.mechanisms.schema import read_drive_motion

MAX_POSITIONS = 1000


def parse(root: Table, meta: Meta) -> PrecisionPositionProblem | None:
    """The problem of the mechanism [linkage] names, read by its home's synthesis face
    (mechanisms.synthesis): the four-bar's and the slider-crank's are `parse_positions`."""
    from linkcli.mechanisms import synthesis
    return synthesis.read("precision-position", root, meta)


def parse_positions(root: Table, meta: Meta) -> PrecisionPositionProblem | None:
    """Positions of a four-bar (output angles) or a slider-crank (slider positions)."""
    from linkcli.mechanisms.synthesis import designers
    link = root.table("linkage", required=True)
    mechanism = read_mechanism(link, designers("precision-position")) if link else "four-bar"
    if link is not None and mechanism is not None and refuse_foreign(link, mechanism):
        mechanism = None
    if mechanism == "slider-crank":
        return parse_slider(root, meta)
    ground = bounded_length(link, "ground") if link else None
    pos = root.table("positions", required=True)
    phi = psi = None
    if pos is not None:
        phi = pos.number_list("input", min_len=3, max_len=MAX_POSITIONS, what="input angles")
        psi = pos.number_list("output", min_len=3, max_len=MAX_POSITIONS, what="output angles")
        if phi is not None and psi is not None and len(phi) != len(psi):
            pos.error("output", f"one output angle per input angle ({len(phi)})", psi)
            return None
    speed, steps = read_drive_motion(root)  # [motion]: the kinematics section's speed and steps
    if mechanism is None or ground is None or phi is None or psi is None or speed is None or steps is None:
        return None
    u = meta.units
    if coincident(pos, phi, u):
        return None
    line = root.reader.line_of(("positions", "input"))
    phi_rad = in_motion_order([u.to_rad(v) for v in phi])
    psi_rad = [u.to_rad(v) for v in psi]
    refused = position_problem(phi_rad, psi_rad, ground)  # as the solver would, but before it
    if refused is not None:
        root.reader.errors.append(SchemaError(*refused, path=meta.path, line=line, key="positions"))
        return None
    return PrecisionPositionProblem(
        meta=meta, ground=ground,
        input_angles=tuple(phi_rad), output_angles=tuple(psi_rad),
        lines=(line,), input_speed=u.to_rad(speed), steps=steps,
    )


def coincident(pos: Table, phi: list[float], u) -> bool:
    """Two input angles equal once wrapped (within 1e-9 of a turn): one located error."""
    full = u.from_rad(2 * math.pi)
    for i in range(len(phi)):
        for j in range(i + 1, len(phi)):
            gap = abs(phi[i] - phi[j]) % full
            if min(gap, full - gap) < 1e-9 * full:
                pos.error("input", "distinct angles, one per position",
                          raw_got=f"positions {i + 1} and {j + 1} at the same angle "
                                  f"({phi[i]:g} and {phi[j]:g} {u.angle})")
                return True
    return False


def within_sizes(pos: Table, s: list[float]) -> bool:
    """Every slider position at most MAX_LENGTH in magnitude, as any coordinate a file holds
    (-1e308 passed `check` and made a linkage no file could hold); else one located error,
    at the first one beyond, and False."""
    for i, value in enumerate(s):
        if abs(value) > MAX_LENGTH:
            pos.error(f"output[{i}]", f"a slider position of magnitude at most {MAX_LENGTH:g} (length unit)",
                      pos.data["output"][i])  # as written
            return False
    return True


def parse_slider(root: Table, meta: Meta) -> PrecisionPositionProblem | None:
    """A slider-crank through (crank angle, slider position) pairs: [linkage] holds only
    `mechanism` (the lengths are the answer); positions.output are slider positions s_i
    (length unit, x of the slider pin). Impossible data (coincident angles, a singular
    system, no finite or nonzero crank, no real rod) is refused here, naming the positions,
    in pure Python (slider_system), so that `check` refuses it too."""
    pos = root.table("positions", required=True)
    phi = s = None
    if pos is not None:
        phi = pos.number_list("input", min_len=3, max_len=MAX_POSITIONS, what="input angles")
        s = pos.number_list("output", min_len=3, max_len=MAX_POSITIONS,
                            what="slider positions (length unit)")
        if phi is not None and s is not None and len(phi) != len(s):
            pos.error("output", f"one slider position per input angle ({len(phi)})", s)
            return None
        if s is not None and not within_sizes(pos, s):
            return None
    speed, steps = read_drive_motion(root)
    if phi is None or s is None or speed is None or steps is None:
        return None
    u = meta.units
    if coincident(pos, phi, u):
        return None
    line = root.reader.line_of(("positions", "input"))
    phi_rad = in_motion_order([u.to_rad(v) for v in phi])
    refused = slider_position_problem(phi_rad, [float(v) for v in s])  # as the solver would
    if refused is not None:
        root.reader.errors.append(SchemaError(*refused, path=meta.path, line=line, key="positions"))
        return None
    return PrecisionPositionProblem(meta=meta, ground=None, input_angles=tuple(phi_rad),
                                    output_angles=tuple(float(v) for v in s), lines=(line,),
                                    input_speed=u.to_rad(speed), steps=steps, mechanism="slider-crank")
