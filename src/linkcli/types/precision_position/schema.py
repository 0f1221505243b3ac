"""Schema of `type = "precision-position"` (Freudenstein function generation)."""

from __future__ import annotations

import math

from linkcli.model import Meta, PrecisionPositionProblem
from linkcli.io.meta import bounded_length, in_motion_order
from linkcli.errors import SchemaError
from linkcli.io.reader import Table
from linkcli.types.precision_position.system import position_problem
from linkcli.types.linkage.schema import read_motion

MAX_POSITIONS = 1000


def parse(root: Table, meta: Meta) -> PrecisionPositionProblem | None:
    link = root.table("linkage", required=True)
    ground = bounded_length(link, "ground") if link else None
    pos = root.table("positions", required=True)
    phi = psi = None
    if pos is not None:
        phi = pos.number_list("input", min_len=3, max_len=MAX_POSITIONS, what="input angles")
        psi = pos.number_list("output", min_len=3, max_len=MAX_POSITIONS, what="output angles")
        if phi is not None and psi is not None and len(phi) != len(psi):
            pos.error("output", f"one output angle per input angle ({len(phi)})", psi)
            return None
    speed, steps = read_motion(root)  # [motion]: the kinematics section's speed and steps
    if ground is None or phi is None or psi is None or speed is None or steps is None:
        return None
    u = meta.units
    full = u.from_rad(2 * math.pi)
    # the one coincident-positions check (the solver trusts it): inputs within 1e-9 of a turn
    for key, values in (("input", phi),):  # equal outputs are legitimate (a rocker returns)
        for i in range(len(values)):
            for j in range(i + 1, len(values)):
                gap = abs(values[i] - values[j]) % full
                if min(gap, full - gap) < 1e-9 * full:
                    pos.error(key, "distinct angles, one per position",
                              raw_got=f"positions {i + 1} and {j + 1} at the same angle "
                                      f"({values[i]:g} and {values[j]:g} {u.angle})")
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
