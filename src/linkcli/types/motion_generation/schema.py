"""Schema of `type = "motion-generation"`: a body guided through poses.

    [target]       poses (>= 2 triples [x, y, angle], global frame, angle in the file's
                   unit), timing ("free" | "prescribed"; default: prescribed when
                   input_angles is given), input_angles (prescribed: one per pose),
                   angle_weight (a positive length; default: the poses' characteristic
                   length, the RMS distance of the pose origins from their centroid)
    [pivots]       ground = [[x, y], [x, y]] (A0, B0, global) or moving = [[x, y], [x, y]]
                   (A, B in the body frame); 2 or 3 poses only (4 or more overdetermine them)
    [bounds]       ground, input, coupler, output, ground_pivot, ground_angle, input_offset
                   (prescribed timing): as path-generation (its helpers)
    [constraints]  grashof, transmission = [lo, hi], branch: as path-generation
    [objective]    minimize = [...] (two or three of OBJECTIVES: a Pareto front,
                   reading.pareto_keys; no [loads] or [tolerance] here, so no torque,
                   pin-force or failure-probability), points, reference_point

A missing bound is None here: the solver fills it from the poses (solve.DEFAULT_*). No numerics.
"""

from __future__ import annotations

import math
from dataclasses import replace

from linkcli.io.reader import MISSING, Table, describe
from linkcli.mechanisms.four_bar.model import LINKS
from linkcli.model import Meta, MotionGenerationProblem
from linkcli.types.path_generation.schema import (
    MAX_MAGNITUDE,
    angle_range,
    length_bound,
    point_range,
    read_constraints,
    read_input_angles,
)

MIN_POSES = 2
MAX_POSES = 200  # free timing adds one input angle per pose to the unknowns
EXACT_POSES = 5  # up to five poses the synthesis is exact (dyads, Burmester); beyond, least squares
PIVOT_POSES = 3  # given pivots fix a dyad for at most three poses
SAME_POSE = 1e-9  # relative (to the poses' extent, and to a full turn): two poses this close are one
TARGET_KEYS = ("poses", "timing", "input_angles", "angle_weight")
BOUND_KEYS = ("ground", "input", "coupler", "output", "ground_pivot", "ground_angle", "input_offset")
OBJECTIVES = ("error", "max-error", "transmission", "size", "link-ratio")  # a front's: what the type measures


def _number_row(item, size: int) -> bool:
    return (isinstance(item, list) and len(item) == size
            and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in item))


def _shown(item) -> str:
    if isinstance(item, list) and 0 < len(item) <= 4:
        return "[" + ", ".join(describe(v) for v in item) + "]"
    return describe(item)


def _poses(t: Table, units):
    """[[x, y, angle], ...]: MIN_POSES to MAX_POSES triples of finite numbers, no two the
    same pose (same origin and the same angle modulo a full turn). Radians out."""
    value = t.raw("poses")
    want = f"an array of {MIN_POSES} to {MAX_POSES} poses [x, y, angle]"
    if value is MISSING or not isinstance(value, list):
        t.error("poses", want, value)
        return None
    if not MIN_POSES <= len(value) <= MAX_POSES:
        t.error("poses", want, raw_got=f"an array of {len(value)}")
        return None
    out = []
    for i, item in enumerate(value):
        if _number_row(item, 3) and all(math.isfinite(v) and abs(v) <= MAX_MAGNITUDE for v in item):
            out.append((float(item[0]), float(item[1]), float(item[2])))
            continue
        t.error(f"poses[{i}]", f"a pose [x, y, angle] of three finite numbers (at most "
                f"{MAX_MAGNITUDE:g} in magnitude)", raw_got=_shown(item))
        return None
    extent = max(max(p[k] for p in out) - min(p[k] for p in out) for k in (0, 1))
    full = units.from_rad(2 * math.pi)
    for i in range(len(out)):
        for j in range(i + 1, len(out)):
            gap = abs(out[i][2] - out[j][2]) % full
            if (math.hypot(out[i][0] - out[j][0], out[i][1] - out[j][1]) <= SAME_POSE * max(extent, 1.0)
                    and min(gap, full - gap) <= SAME_POSE * full):
                t.error("poses", "distinct poses (no two with the same origin and angle)",
                        raw_got=f"poses {i + 1} and {j + 1} are the same pose")
                return None
    return [(x, y, units.to_rad(a)) for x, y, a in out]


def _pivot_pair(t: Table, key: str, n: int | None, timing: str | None):
    """[[x, y], [x, y]]: two distinct points of finite numbers; allowed for 2 or 3 poses
    (free timing), ground pivots also with prescribed timing (they are then fixed)."""
    value = t.raw(key)
    want = "two pivots [[x, y], [x, y]] of finite numbers"
    if not isinstance(value, list) or len(value) != 2:
        t.error(key, want, raw_got=_shown(value) if not isinstance(value, list)
                else f"an array of {len(value)}")
        return None
    pts = []
    for i, item in enumerate(value):
        if not (_number_row(item, 2) and all(math.isfinite(v) and abs(v) <= MAX_MAGNITUDE for v in item)):
            t.error(f"{key}[{i}]", f"a point [x, y] of two finite numbers (at most {MAX_MAGNITUDE:g} in "
                    "magnitude)", raw_got=_shown(item))
            return None
        pts.append((float(item[0]), float(item[1])))
    if pts[0] == pts[1]:
        t.error(key, "two distinct pivots", raw_got=f"both at [{pts[0][0]:g}, {pts[0][1]:g}]")
        return None
    if timing == "prescribed" and key == "moving":
        t.error(key, 'no moving pivots with timing = "prescribed" (give ground pivots, or use '
                'timing = "free")', raw_got=_shown(value))
        return None
    if n is not None and timing == "free" and n > PIVOT_POSES:
        t.error(key, f"pivots for 2 or 3 poses only (with {n} poses the dyads are fixed by the poses: "
                "given pivots overdetermine them; use [bounds] ground_pivot instead)",
                raw_got=f"{key} pivots with {n} poses")
        return None
    return tuple(pts)


def parse(root: Table, meta: Meta):
    """The problem of the mechanism [linkage] names, read by its home's synthesis face
    (mechanisms.synthesis): the four-bar's below (`parse_four_bar`), another home's keys."""
    from linkcli.mechanisms import synthesis
    return synthesis.read("motion-generation", root, meta)


def parse_four_bar(root: Table, meta: Meta) -> MotionGenerationProblem | None:
    """A four-bar's coupler guiding a body through poses (the module docstring's keys)."""
    u = meta.units
    tgt = root.table("target", required=True)
    if tgt is None:
        return None
    tgt.allow(*TARGET_KEYS)
    poses = _poses(tgt, u)
    n = len(poses) if poses is not None else None
    timing = tgt.string("timing", "prescribed" if "input_angles" in tgt else "free",
                        choices=("prescribed", "free"))
    angles = (read_input_angles(tgt, timing, n, u, item="pose", max_len=MAX_POSES) if poses is not None and timing is not None else None)
    weight = None
    if "angle_weight" in tgt:
        weight = tgt.number("angle_weight", positive=True, hi=MAX_MAGNITUDE, what="a positive length")

    piv = root.table("pivots")
    ground_pivots = moving_pivots = None
    pivots_ok = True
    if piv is not None:
        piv.allow("ground", "moving")
        if "ground" in piv and "moving" in piv:
            piv.error("moving", "ground or moving pivots, not both (either fixes the dyads for 2 or 3 "
                      "poses)", raw_got="both ground and moving")
            pivots_ok = False
        elif "ground" in piv:
            ground_pivots = _pivot_pair(piv, "ground", n, timing)
            pivots_ok = ground_pivots is not None
        elif "moving" in piv:
            moving_pivots = _pivot_pair(piv, "moving", n, timing)
            pivots_ok = moving_pivots is not None

    bnd = root.table("bounds")
    if bnd is not None:
        bnd.allow(*BOUND_KEYS)
    lengths = {k: length_bound(bnd, k, None) if bnd is not None and k in bnd else None for k in LINKS}
    lengths_ok = all(lengths[k] is not None for k in LINKS if bnd is not None and k in bnd)
    gp = point_range(bnd, "ground_pivot", ())
    ga = angle_range(bnd, "ground_angle", (), u)
    offset = None
    offset_ok = True
    if bnd is not None and "input_offset" in bnd:
        if timing == "free":
            bnd.error("input_offset", 'no input_offset with timing = "free" (every input angle is free)',
                      raw_got=describe(bnd.raw("input_offset")))
            offset_ok = False
        else:
            offset = angle_range(bnd, "input_offset", None, u)
            offset_ok = offset is not None

    grashof, branch, window, window_ok = read_constraints(root, u)
    from linkcli.reading.pareto_keys import read_front
    front_ok, front = read_front(root, meta, OBJECTIVES)  # [objective] minimize = [...]: a Pareto front
    meta = replace(meta, front=front) if front is not None else meta

    if (not front_ok or poses is None or timing is None or angles is None or (weight is None and "angle_weight" in tgt)
            or not pivots_ok or not lengths_ok or gp is None or ga is None or not offset_ok
            or grashof is None or branch is None or not window_ok):
        return None
    lines = {k: root.reader.line_of(k) for k in (("target", "poses"), ("target", "input_angles"),
                                                 ("pivots",), ("bounds",), ("constraints",))}
    return MotionGenerationProblem(
        meta=meta, poses=tuple(poses), timing=timing,
        input_angles=angles if timing == "prescribed" else None, angle_weight=weight,
        ground_pivots=ground_pivots, moving_pivots=moving_pivots, lengths=lengths,
        ground_pivot=gp or None, ground_angle=ga or None, input_offset=offset,
        grashof=grashof, transmission=window, branch=branch,
        lines={".".join(k): v for k, v in lines.items()},
    )
