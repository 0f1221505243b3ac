"""Schema of `type = "path-generation"`: a coupler point through target points.

    [target]       points (>= 3 pairs [x, y]), timing ("prescribed" | "free"; default:
                   prescribed when input_angles is given), input_angles (prescribed: one
                   per point, local frame), direction (free: "ccw" | "cw" | "either")
    [bounds]       ground, input, coupler, output, ground_angle, input_offset: a number
                   (fixed) or [lo, hi]; coupler_point, ground_pivot: { x = ..., y = ... }
    [constraints]  grashof, transmission = [lo, hi], branch; defect_free (robust design)
    [objective]    minimize = "error" | "failure-probability" (reading.robust_keys)

A missing bound defaults to a box scaled on the targets (see DEFAULT_SPAN). No numerics.
"""

from __future__ import annotations

import math

from linkcli.model import Meta, PathGenerationProblem
from linkcli.mechanisms.four_bar.model import LINKS
from linkcli.reading.meta import in_motion_order
from linkcli.io.bounds import MAX_LENGTH, MIN_LENGTH
from linkcli.reading.robust_keys import read_objective
from linkcli.io.reader import MISSING, Table, describe

GRASHOF = ("any", "crank-rocker", "double-crank", "rocker-crank", "double-rocker", "triple-rocker")
BRANCHES = ("open", "crossed", "either")
DIRECTIONS = ("either", "ccw", "cw")
MIN_POINTS = 3
MAX_POINTS = 1000
MAX_FREE_POINTS = 200
MAX_MAGNITUDE = MAX_LENGTH  # coordinates, lengths and angles beyond this are typing errors
# MIN_LENGTH (common): a length bound below it, other than a lower bound of 0, is a typing error
TARGET_KEYS = ("points", "timing", "input_angles", "direction")
BOUND_KEYS = ("ground", "input", "coupler", "output", "coupler_point", "ground_pivot", "ground_angle",
              "input_offset")
DEFAULT_SPAN = 5.0  # a missing bound: lengths (0, 5 R], points within 5 R (R: the targets' extent)


def _points(t: Table):
    """[[x, y], ...]: at least MIN_POINTS pairs of finite numbers, not all the same."""
    value = t.raw("points")
    want = f"an array of {MIN_POINTS} to {MAX_POINTS} points [x, y]"
    if value is MISSING or not isinstance(value, list) or not MIN_POINTS <= len(value) <= MAX_POINTS:
        t.error("points", want, value)
        return None
    out = []
    for i, item in enumerate(value):
        ok = (isinstance(item, list) and len(item) == 2
              and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in item))
        if ok and all(math.isfinite(v) and abs(v) <= MAX_MAGNITUDE for v in item):
            out.append((float(item[0]), float(item[1])))
            continue
        got = ("[" + ", ".join(describe(v) for v in item) + "]"
               if isinstance(item, list) and 0 < len(item) <= 4 else describe(item))
        t.error(f"points[{i}]", f"a point [x, y] of two finite numbers (at most {MAX_MAGNITUDE:g} in "
                "magnitude)", raw_got=got)
        return None
    if len(set(out)) == 1:
        t.error("points", "points that are not all the same", raw_got=f"{len(out)} copies of "
                f"[{out[0][0]:g}, {out[0][1]:g}]")
        return None
    extent = max(max(p[0] for p in out) - min(p[0] for p in out),
                 max(p[1] for p in out) - min(p[1] for p in out))
    if extent < MIN_LENGTH:
        t.error("points", f"points spread over at least {MIN_LENGTH:g} (length unit)",
                raw_got=f"points within {extent:.3g} of one another")
        return None
    return out


def read_constraints(root: Table, u):
    """[constraints] of a coupler-point synthesis (path or motion generation): grashof
    (default "any"), branch (default "either"), transmission window (None: no window);
    (grashof, branch, window, window_ok), None for a value in error."""
    con = root.table("constraints")
    grashof, branch, window, window_ok = "any", "either", None, True
    if con is not None:
        con.allow("grashof", "transmission", "branch")
        grashof = con.string("grashof", "any", choices=GRASHOF)
        branch = con.string("branch", "either", choices=BRANCHES)
        window, window_ok = transmission_window(con, u)
    return grashof, branch, window, window_ok


def read_input_angles(t: Table, timing: str, n: int, units, item: str = "point", max_len: int = MAX_POINTS):
    """Prescribed timing: one input angle per `item` (a path's point, a body's pose), distinct
    modulo a full turn, taken in the order of motion (rad)."""
    given = "input_angles" in t
    if timing == "free":
        if given:
            t.error("input_angles", 'no input_angles with timing = "free" (the solver chooses them; '
                    'use timing = "prescribed")', raw_got=describe(t.raw("input_angles")))
        return ()
    if not given:
        t.error("input_angles", f'an array of input angles, one per {item} (timing = "prescribed")')
        return None
    angles = t.number_list("input_angles", max_len=max_len, what="input angles")
    if angles is None:
        return None
    if max(abs(v) for v in angles) > MAX_MAGNITUDE:
        t.error("input_angles", f"input angles of at most {MAX_MAGNITUDE:g} in magnitude",
                raw_got=f"{max(angles, key=abs):g}")
        return None
    if len(angles) != n:
        t.error("input_angles", f"one input angle per {item} ({n})", raw_got=f"an array of {len(angles)}")
        return None
    full = units.from_rad(2 * math.pi)
    for i in range(n):
        for j in range(i + 1, n):
            gap = abs(angles[i] - angles[j]) % full
            if min(gap, full - gap) < 1e-9 * full:
                t.error("input_angles", f"distinct input angles (modulo a full turn), one per {item}",
                        raw_got=f"{item}s {i + 1} and {j + 1} at the same angle "
                                f"({angles[i]:g} and {angles[j]:g} {units.angle})")
                return None
    return tuple(in_motion_order([units.to_rad(v) for v in angles]))


def length_bound(t: Table | None, key: str, default):
    """A length bound: a number within [MIN_LENGTH, MAX_MAGNITUDE] (fixed), or [lo, hi] with
    lo = 0 or lo >= MIN_LENGTH, and MIN_LENGTH <= hi <= MAX_MAGNITUDE (the range kinematics
    keeps full precision over, as for linkage files)."""
    if t is None or key not in t:
        return default
    want = (f"a length within [{MIN_LENGTH:g}, {MAX_MAGNITUDE:g}], or a range [lo, hi] of such "
            "lengths (lo may be 0)")
    value = t.raw(key)
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        if not (math.isfinite(value) and MIN_LENGTH <= value <= MAX_MAGNITUDE):
            t.error(key, want, raw_got=describe(value))
            return None
    r = t.range(key, nonnegative=True)
    if r is None:
        return None
    lo, hi = r
    if not (MIN_LENGTH <= hi <= MAX_MAGNITUDE and (lo == 0.0 or lo >= MIN_LENGTH)):
        t.error(key, want, raw_got=f"[{lo:g}, {hi:g}]" if isinstance(value, list) else describe(value))
        return None
    return r


def _limited(t: Table, key: str, r, what: str = "a bound"):
    """r unless one of its ends exceeds MAX_MAGNITUDE (error recorded, None)."""
    if r is not None and max(abs(r[0]), abs(r[1])) > MAX_MAGNITUDE:
        t.error(key, f"{what} of at most {MAX_MAGNITUDE:g} in magnitude",
                raw_got=f"[{r[0]:g}, {r[1]:g}]" if r[0] != r[1] else f"{r[0]:g}")
        return None
    return r


def angle_range(t: Table | None, key: str, default, units):
    if t is None or key not in t:
        return default
    r = _limited(t, key, t.range(key), "an angle")
    return None if r is None else (units.to_rad(r[0]), units.to_rad(r[1]))


def point_range(t: Table | None, key: str, default):
    if t is None or key not in t:
        return default
    r = t.point_range(key)
    if r is None:
        return None
    sub = t.table(key)
    xr, yr = _limited(sub, "x", r[0], "a coordinate"), _limited(sub, "y", r[1], "a coordinate")
    return None if xr is None or yr is None else (xr, yr)


def transmission_window(t: Table, units):
    """transmission = [lo, hi]: 0 <= lo < hi <= 180 deg (pi rad); radians out."""
    if "transmission" not in t:
        return None, True
    w = t.number_list("transmission", length=2, what="angles [lo, hi]")
    if w is None:
        return None, False
    top = units.from_rad(math.pi)
    if not 0.0 <= w[0] < w[1] <= top:
        t.error("transmission", f"a window [lo, hi] with 0 <= lo < hi <= {top:g} ({units.angle})",
                raw_got=f"[{w[0]:g}, {w[1]:g}]")
        return None, False
    return (units.to_rad(w[0]), units.to_rad(w[1])), True


def parse(root: Table, meta: Meta):
    """The problem of the mechanism [linkage] names, read by its home's synthesis face
    (mechanisms.synthesis): the four-bar's below (`parse_four_bar`), another home's keys."""
    from linkcli.mechanisms import synthesis
    return synthesis.read("path-generation", root, meta)


def parse_four_bar(root: Table, meta: Meta) -> PathGenerationProblem | None:
    """A four-bar's coupler point through target points (the module docstring's keys)."""
    u = meta.units
    tgt = root.table("target", required=True)
    if tgt is None:
        return None
    tgt.allow(*TARGET_KEYS)
    points = _points(tgt)
    timing = tgt.string("timing", "prescribed" if "input_angles" in tgt else "free",
                        choices=("prescribed", "free"))
    direction = "either"
    if timing == "free":
        direction = tgt.string("direction", "either", choices=DIRECTIONS)
    elif timing == "prescribed" and "direction" in tgt:
        tgt.error("direction", 'no direction with timing = "prescribed" (the input angles set it)',
                  raw_got=describe(tgt.raw("direction")))
    angles = (read_input_angles(tgt, timing, len(points), u)
              if points is not None and timing is not None else None)

    bnd = root.table("bounds")
    if bnd is not None:
        bnd.allow(*BOUND_KEYS)
    ok = points is not None
    if ok and timing == "free" and len(points) > MAX_FREE_POINTS:
        tgt.error("points", f"at most {MAX_FREE_POINTS} points with free timing (each point adds "
                  "an input angle to the unknowns)", raw_got=f"an array of {len(points)}")
        ok = False
    if ok:
        xs, ys = [p[0] for p in points], [p[1] for p in points]
        extent = max(max(xs) - min(xs), max(ys) - min(ys))
        cx, cy = 0.5 * (max(xs) + min(xs)), 0.5 * (max(ys) + min(ys))
        span = min(DEFAULT_SPAN * extent, MAX_LENGTH)  # defaults within the sizes any file accepts
    else:
        extent, cx, cy, span = 1.0, 0.0, 0.0, 1.0

    def within(lo: float, hi: float) -> tuple[float, float]:  # a result `analyze` reads again
        return max(lo, -MAX_LENGTH), min(hi, MAX_LENGTH)

    lengths = {k: length_bound(bnd, k, (0.0, span)) for k in LINKS}
    cp = point_range(bnd, "coupler_point", ((-span, span), (-span, span)))
    gp = point_range(bnd, "ground_pivot", (within(cx - span, cx + span), within(cy - span, cy + span)))
    ga = angle_range(bnd, "ground_angle", (0.0, 2 * math.pi), u)
    offset = None
    if bnd is not None and "input_offset" in bnd:
        if timing == "free":
            bnd.error("input_offset", 'no input_offset with timing = "free" (every input angle is free)',
                      raw_got=describe(bnd.raw("input_offset")))
        else:
            offset = angle_range(bnd, "input_offset", None, u)
            ok = ok and offset is not None

    grashof, branch, window, window_ok = read_constraints(root, u)
    robust = read_objective(root, meta)  # [objective] minimize, [constraints] defect_free

    if (not ok or timing is None or direction is None or angles is None or None in lengths.values()
            or cp is None or gp is None or ga is None or grashof is None or branch is None
            or not window_ok or robust is None):
        return None
    lines = {k: root.reader.line_of(k) for k in (("target", "points"), ("target", "input_angles"),
                                                 ("bounds",), ("constraints",))}
    return PathGenerationProblem(
        meta=meta, points=tuple(points), timing=timing,
        input_angles=angles if timing == "prescribed" else None, direction=direction,
        lengths=lengths, coupler_point=cp, ground_pivot=gp, ground_angle=ga, input_offset=offset,
        grashof=grashof, transmission=window, branch=branch,
        lines={".".join(k): v for k, v in lines.items()}, objective=robust[0], defect_free=robust[1],
    )
