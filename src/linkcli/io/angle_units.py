"""A note when a file's angles look written in the other unit: degrees in a file whose
`[units] angle = "rad"`, or radians in a degree file. Only a note, never an error: a
mechanism may legitimately turn 30 rad, or sweep 3 deg. Pure Python (no numpy), on the
parsed TOML.

Rules: in a rad file, an angle of magnitude above 8 pi (four turns) looks like degrees;
in a deg file, angles that are all within 2 pi in magnitude, not all 0, and more than one
value, look like radians (any real deg file names some angle above 6.28: a sweep, a
position, a transmission limit).
"""

from __future__ import annotations

import math

from linkcli.textnum import num

ANGLE_KEYS = (  # (table, key) of the angles a problem file may hold (docs/format.md)
    ("positions", "input"), ("positions", "output"),
    ("target", "input_sweep"), ("target", "output_sweep"), ("target", "input_start"),
    ("target", "output_start"), ("target", "input_angles"),
    ("bounds", "input_start"), ("bounds", "output_start"), ("bounds", "ground_angle"),
    ("bounds", "input_offset"), ("motion", "start"), ("motion", "end"),
    ("constraints", "transmission"), ("linkage", "ground_angle"),
)
RAD_LOOKS_LIKE_DEG = 8 * math.pi
DEG_LOOKS_LIKE_RAD = 2 * math.pi


def _numbers(value) -> list[float]:
    if isinstance(value, bool):
        return []
    if isinstance(value, (int, float)):
        return [float(value)] if math.isfinite(float(value)) else []
    if isinstance(value, list):
        return [x for item in value for x in _numbers(item)]
    return []


def angle_unit_note(data: dict, angle_unit: str) -> str | None:
    """The note for a file whose angles look like the other unit, or None."""
    found: list[tuple[str, float]] = []
    for table, key in ANGLE_KEYS:
        node = data.get(table)
        if isinstance(node, dict) and key in node:
            found += [(f"{table}.{key}", x) for x in _numbers(node[key])]
    if not found:
        return None
    if angle_unit == "rad":
        big = [(k, x) for k, x in found if abs(x) > RAD_LOOKS_LIKE_DEG]
        if big:
            key, x = big[0]
            return (f"{key} = {num(x)} rad is more than four turns: if the file's angles are in degrees, "
                    'write [units] angle = "deg"')
        return None
    values = [x for _, x in found]
    if len(values) > 1 and any(x != 0.0 for x in values) and all(abs(x) <= DEG_LOOKS_LIKE_RAD for x in values):
        keys = ", ".join(dict.fromkeys(k for k, _ in found))
        return (f"every angle ({keys}) is within 2 pi in a degree file: if they are in radians, "
                'write [units] angle = "rad"')
    return None
