"""Schema of `type = "quick-return"`: a crank-rocker or slider-crank by its time ratio.

    mechanism      "crank-rocker" | "slider-crank"
    time_ratio     K >= 1: slow stroke over fast stroke at constant crank speed
    swing          crank-rocker: rocker swing (angle unit), 0 < swing < 180 deg
    stroke         slider-crank: slider stroke (length unit)
    [linkage]      crank-rocker: exactly one of ground | output (the scale);
                   slider-crank: offset (optional, signed; without it the offset is free)
    [bounds]       ranges [lo, hi] on `parameter` and on the lengths the solver chooses
    [constraints]  transmission = [lo, hi] over the full turn

Every condition a closed form decides is checked here, in plain math (`check` imports no
numpy; the same conditions guard the numerical core, family.py). With the dead-centre
angle theta = 180 deg (K - 1) / (K + 1) (geometry.py):
- a crank-rocker of swing s exists iff theta < 90 deg + s / 2 (the crank pivot must see the
  chord of the rocker's extreme pins under theta from a point on the same side of both);
- a slider-crank exists iff theta < 90 deg (K < 3);
- a given offset e needs 0 < |e| < stroke cot(theta) (e = 0 iff K = 1: in-line).
Whether any member lies within [bounds] and the documented link ratio takes the family
itself: the solver reports that, located (SolveInputError, exit 2).
"""

from __future__ import annotations

import math

from linkcli.io.bounds import MAX_LENGTH, bounded_length
from linkcli.io.reader import Table
from linkcli.model import Meta, QuickReturnProblem

MECHANISMS = ("crank-rocker", "slider-crank")
SCALES = ("ground", "output")
BOUND_KEYS = {"crank-rocker": ("parameter", "input", "coupler", "output", "ground"),
              "slider-crank": ("parameter", "input", "coupler", "offset")}
OTHER = {"crank-rocker": "slider-crank", "slider-crank": "crank-rocker"}


def dead_centre_angle_deg(time_ratio: float) -> float:
    """theta = 180 deg (K - 1) / (K + 1)."""
    return 180.0 * (time_ratio - 1.0) / (time_ratio + 1.0)


def crank_rocker_ratio_limit(swing_deg: float) -> float:
    """The time ratio a crank-rocker of this swing stays below: theta < 90 + swing / 2,
    K = (180 + theta) / (180 - theta)."""
    return (270.0 + 0.5 * swing_deg) / (90.0 - 0.5 * swing_deg)


def offset_limit(stroke: float, time_ratio: float) -> float:
    """stroke cot(theta): the largest |offset| (excluded) of a slider-crank whose crank turns."""
    theta = math.radians(dead_centre_angle_deg(time_ratio))
    return stroke * math.cos(theta) / math.sin(theta) if theta > 0.0 else 0.0


def parse(root: Table, meta: Meta) -> QuickReturnProblem | None:
    u = meta.units
    root.allow("swing", "stroke")
    mechanism = root.string("mechanism", choices=MECHANISMS)
    ratio = read_time_ratio(root)
    link = root.table("linkage", required=mechanism == "crank-rocker")
    if link is not None:
        link.allow("ground", "output", "offset")
    swing = stroke = scale = offset = None
    ok = mechanism is not None and ratio is not None
    if mechanism == "crank-rocker":
        refuse(root, "stroke", mechanism, "a crank-rocker takes swing")
        swing = read_swing(root, u)
        if link is not None:
            refuse(link, "offset", mechanism, "a crank-rocker's [linkage] takes ground or output")
        scale = read_scale(link) if link is not None else None
        if swing is not None and ratio is not None:
            ok &= crank_rocker_exists(root, ratio, swing, u)
        ok &= swing is not None and scale is not None
    elif mechanism == "slider-crank":
        refuse(root, "swing", mechanism, "a slider-crank takes stroke")
        stroke = bounded_length(root, "stroke")
        if link is not None:
            for k in SCALES:
                refuse(link, k, mechanism, "a slider-crank has no ground or output link; "
                                           "its [linkage] takes offset")
            offset = link.number("offset", None, lo=-MAX_LENGTH, hi=MAX_LENGTH,
                                 what="a signed offset (length unit)")
            ok &= "offset" not in link or offset is not None
        if ratio is not None:
            ok &= slider_crank_exists(root, ratio)
        if ok and stroke is not None and offset is not None:
            ok &= offset_fits(link, offset, stroke, ratio)
        ok &= stroke is not None
    bounds = read_bounds(root, mechanism, scale, offset)
    window = read_window(root, u)
    if not ok or bounds is None or window is False or len(root.reader.errors):
        return None
    line = root.reader.line_of
    keys = ["time_ratio", "swing", "stroke", "mechanism", "linkage", "linkage.ground",
            "linkage.output", "linkage.offset", "bounds", "constraints.transmission"]
    keys += [f"bounds.{k}" for k in bounds]
    lines = {k: line(tuple(k.split("."))) for k in keys}
    return QuickReturnProblem(meta=meta, mechanism=mechanism, time_ratio=ratio,
                              swing=u.to_rad(swing) if swing is not None else None,
                              stroke=stroke, scale=scale, offset=offset, bounds=bounds,
                              transmission=window, lines=lines)


def refuse(t: Table, key: str, mechanism: str, takes: str) -> None:
    """A key that belongs to the other mechanism."""
    if key in t:
        t.error(key, f'no {key} for mechanism = "{mechanism}" ({key} belongs to '
                     f'"{OTHER[mechanism]}"; {takes})', t.raw(key))


def read_time_ratio(root: Table):
    ratio = root.number("time_ratio", what="a time ratio K >= 1 (slow stroke over fast stroke)")
    if ratio is not None and ratio < 1.0:
        root.error("time_ratio", "a time ratio K >= 1 (slow stroke over fast stroke)", root.raw("time_ratio"))
        return None
    return ratio


def read_swing(root: Table, u):
    """The rocker swing in the file's angle unit, strictly between 0 and 180 deg."""
    top = float(u.from_rad(math.pi))
    what = f"an angle strictly between 0 and {_fmt(top)} ({u.angle})"
    swing = root.number("swing", what=what)
    if swing is not None and not 0.0 < swing < top:
        root.error("swing", what, root.raw("swing"))
        return None
    return swing


def read_scale(link: Table):
    """("ground" | "output", length): exactly one of the two."""
    given = [k for k in SCALES if k in link]
    if not given:
        link.error(None, "the scale: ground or output (a length)", raw_got="neither")
        return None
    if len(given) == 2:
        link.raw("ground")
        link.error("output", "one scale, ground or output, not both",
                   raw_got=f"ground = {_show(link.raw('ground'))} and output = {_show(link.raw('output'))}")
        return None
    value = bounded_length(link, given[0])
    return None if value is None else (given[0], value)


def crank_rocker_exists(root: Table, ratio: float, swing: float, u) -> bool:
    """theta < 90 deg + swing / 2 (module docstring)."""
    swing_deg = math.degrees(u.to_rad(swing))
    if dead_centre_angle_deg(ratio) < 90.0 + 0.5 * swing_deg:
        return True
    root.error("time_ratio", f"a time ratio below {crank_rocker_ratio_limit(swing_deg):.6g} for "
               f"swing {_fmt(swing)} {u.angle} (a crank-rocker needs the dead-centre angle "
               "180 (K - 1) / (K + 1) below 90 + swing / 2 deg)", root.raw("time_ratio"))
    return False


def slider_crank_exists(root: Table, ratio: float) -> bool:
    """theta < 90 deg, i.e. K < 3."""
    if ratio < 3.0:
        return True
    root.error("time_ratio", "a time ratio below 3 for a slider-crank (dead-centre angle "
               "180 (K - 1) / (K + 1) below 90 deg)", root.raw("time_ratio"))
    return False


def offset_fits(link: Table, offset: float, stroke: float, ratio: float) -> bool:
    """0 < |e| < stroke cot(theta); e = 0 only (and then free of it) for K = 1."""
    if ratio == 1.0:
        if offset != 0.0:
            link.error("offset", "offset 0 for time ratio 1 (only an in-line slider-crank has "
                                 "equal strokes)", link.raw("offset"))
            return False
        return True
    if offset == 0.0:
        link.error("offset", f"a nonzero offset for time ratio {_fmt(ratio)} (an in-line "
                             "slider-crank has time ratio 1)", link.raw("offset"))
        return False
    limit = offset_limit(stroke, ratio)
    if abs(offset) >= limit:
        link.error("offset", f"an offset of magnitude below stroke cot(theta) = {limit:.6g} for "
                             f"stroke {_fmt(stroke)} and time ratio {_fmt(ratio)} (beyond, the "
                             "crank cannot turn fully)", link.raw("offset"))
        return False
    return True


def read_bounds(root: Table, mechanism: str | None, scale, offset) -> dict | None:
    """{key: (lo, hi)}; the keys a mechanism's free family has (module docstring)."""
    bnd = root.table("bounds")
    if bnd is None or mechanism is None:
        if bnd is not None:
            bnd.allow(*bnd.keys())
        return {}
    if mechanism == "slider-crank" and offset is not None:
        bnd.allow(*bnd.keys())
        bnd.error(None, "no [bounds] with a given offset (the slider-crank is then unique; "
                        "leave the offset out to make it free)",
                  raw_got=f"bounds on {', '.join(bnd.keys()) or 'nothing'}")
        return None
    out, ok = {}, True
    for key in BOUND_KEYS[mechanism]:
        if key not in bnd:
            continue
        if scale is not None and key == scale[0]:
            bnd.error(key, f"no bounds on {key}: [linkage] {key} sets the scale",
                      raw_got=_show(bnd.raw(key)))
            ok = False
            continue
        signed = mechanism == "crank-rocker" and key == "parameter"
        nonneg = key in ("parameter", "offset") and not signed
        rng = bnd.range(key, positive=not signed and not nonneg, nonnegative=nonneg)
        if rng is not None and max(abs(rng[0]), abs(rng[1])) > MAX_LENGTH:
            bnd.error(key, f"a range within [-{MAX_LENGTH:g}, {MAX_LENGTH:g}]",
                      raw_got=f"[{_fmt(rng[0])}, {_fmt(rng[1])}]")
            rng = None
        if rng is None:
            ok = False
        else:
            out[key] = rng
    return out if ok else None


def read_window(root: Table, u):
    """(lo, hi) in rad, None without [constraints] transmission, False when bad."""
    con = root.table("constraints")
    if con is None or "transmission" not in con:
        return None
    top = float(u.from_rad(math.pi))
    w = con.number_list("transmission", length=2, what="angles [lo, hi]")
    if w is not None and not 0 <= w[0] < w[1] <= top:
        con.error("transmission", f"a window [lo, hi] with 0 <= lo < hi <= {_fmt(top)} ({u.angle})",
                  raw_got=f"[{_fmt(w[0])}, {_fmt(w[1])}]")
        return False
    return False if w is None else (u.to_rad(w[0]), u.to_rad(w[1]))


def _show(value) -> str:
    if isinstance(value, list):
        return "[" + ", ".join(_show(v) for v in value) + "]"
    return _fmt(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else repr(value)


def _fmt(x: float) -> str:
    if not math.isfinite(x):
        return "nan" if math.isnan(x) else ("inf" if x > 0 else "-inf")
    return repr(int(x)) if float(x).is_integer() and abs(x) < 1e15 else f"{x:.6g}"
