"""Schema of a five-bar's path generation: `type = "path-generation"` with `[linkage] mechanism
= "five-bar"` (docs/five_bar.md, "Design"). Pure Python (`check` reads it without numpy).

    [linkage]      mechanism = "five-bar" (nothing else: the lengths are the answer)
    [target]       points = [[x, y], ...]: the path P must follow (>= 2 points, global frame)
    [bounds]       ground, input, input2, coupler, coupler2: a number (fixed) or [lo, hi];
                   ground_pivot = { x = ..., y = ... } (A0); ground_angle (A0 -> B0)
    [constraints]  modes = ["+", "-"] (default) or "any" (each of the four pairs tried);
                   branch = "left" | "right" | "either" (default); max_condition (>= 1: the
                   worst condition number allowed along the path, with maximize =
                   "conditioning"); min_transmission (angle in (0, 90]: the smallest
                   transmission angle's distance from 0 and 180 allowed, with maximize =
                   "transmission")
    [objective]    maximize = "conditioning" (default) | "transmission"; minimize =
                   "failure-probability" (needs [tolerance] with allowed_error) adds the
                   trade-off table of `tradeoff` rows (2 .. 20, default 5)

Missing bounds default as a four-bar's (path_generation.schema.DEFAULT_SPAN): lengths up to
5 R, the pivot within 5 R of the path's centre (R: the path's extent), any ground angle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar

from linkcli.io.reader import Table, describe
from linkcli.mechanisms.five_bar.model import MODES, SIDES
from linkcli.mechanisms.five_bar.schema import MAX_ROWS, MIN_PATH, pairs
from linkcli.model import Meta
from linkcli.types.path_generation.schema import DEFAULT_SPAN, angle_range, length_bound, point_range

LENGTHS = ("ground", "input", "input2", "coupler", "coupler2")
BOUND_KEYS = LENGTHS + ("ground_pivot", "ground_angle")
MEASURES = ("conditioning", "transmission")
ALL_MODES = (("+", "-"), ("+", "+"), ("-", "-"), ("-", "+"))  # "any": tried in this order (ties: the first)
MAX_TRADEOFF = 20


@dataclass(frozen=True)
class FiveBarPathProblem:
    """A five-bar whose output point follows a path, designed for its worst quality along it.
    `bounds`: VARIABLES (mechanisms.five_bar.synthesis) -> (lo, hi), lengths in the length
    unit, the angle in rad; `floor`: the quality every row must keep (1 / max_condition or
    sin(min_transmission)), None without one."""

    mechanism: ClassVar[str] = "five-bar"
    methods: ClassVar[tuple[str, ...]] = ("auto",)  # its one search ([solver] method, bench settings)
    meta: Meta
    points: tuple[tuple[float, float], ...]
    bounds: dict
    modes: tuple[tuple[str, str], ...]
    branch: str = "either"
    maximize: str = "conditioning"
    floor: float | None = None
    minimize: str | None = None
    tradeoff: int = 5
    lines: dict = field(default_factory=dict)


def _modes(con: Table | None):
    if con is None or "modes" not in con:
        return (("+", "-"),)
    value = con.raw("modes")
    if value == "any":
        return ALL_MODES
    if isinstance(value, list) and len(value) == 2 and all(isinstance(v, str) and v in MODES for v in value):
        return ((value[0], value[1]),)
    con.error("modes", 'each chain\'s working mode, two of "+" and "-" (["+", "-"]), or "any"',
              raw_got=describe(value) if not isinstance(value, list) else
              "[" + ", ".join(describe(v) for v in value[:4]) + "]")
    return None


def _floor(con: Table | None, maximize: str, units):
    """max_condition (conditioning) or min_transmission (transmission) as a quality floor."""
    if con is None:
        return None, True
    key, other = ("max_condition", "min_transmission") if maximize == "conditioning" else \
        ("min_transmission", "max_condition")
    if other in con:
        con.raw(other)
        con.error(other, f'{key} with maximize = "{maximize}" ({other} goes with the other measure)',
                  raw_got=f"{other} = {describe(con.data[other])}")
        return None, False
    if key not in con:
        return None, True
    if key == "max_condition":
        v = con.number(key, lo=1.0, hi=1e12, what="a condition number")
        return (None, False) if v is None else (1.0 / v, True)
    top = units.from_rad(math.pi / 2)
    v = con.number(key, what=f"an angle in (0, {top:g}] ({units.angle})")
    if v is not None and not 0.0 < v <= top:
        con.error(key, f"an angle in (0, {top:g}] ({units.angle})", v)
        v = None
    return (None, False) if v is None else (math.sin(units.to_rad(v)), True)


def parse(root: Table, meta: Meta) -> FiveBarPathProblem | None:
    u = meta.units
    link = root.table("linkage")
    link.string("mechanism")  # five-bar, or this parser would not run
    tgt = root.table("target", required=True)
    points = pairs(tgt, "points", "points [x, y] of the path (length unit)", MIN_PATH, 1e9) if tgt else None
    if points is not None and len(set(points)) == 1:
        tgt.error("points", "points that are not all the same", raw_got=f"{len(points)} copies of {list(points[0])}")
        points = None
    bnd = root.table("bounds")
    if bnd is not None:
        bnd.allow(*BOUND_KEYS)
    if points is not None:
        xs, ys = [p[0] for p in points], [p[1] for p in points]
        extent = max(max(xs) - min(xs), max(ys) - min(ys))
        cx, cy = 0.5 * (max(xs) + min(xs)), 0.5 * (max(ys) + min(ys))
        span = DEFAULT_SPAN * extent
    else:
        cx, cy, span = 0.0, 0.0, 1.0
    lengths = {k: length_bound(bnd, k, (0.0, span)) for k in LENGTHS}
    gp = point_range(bnd, "ground_pivot", ((cx - span, cx + span), (cy - span, cy + span)))
    ga = angle_range(bnd, "ground_angle", (0.0, 2 * math.pi), u)
    obj = root.table("objective")
    maximize, minimize, tradeoff = "conditioning", None, 5
    if obj is not None:
        maximize = obj.string("maximize", "conditioning", choices=MEASURES)
        minimize = obj.string("minimize", None, choices=("failure-probability",))
        if "tradeoff" in obj and minimize is None:
            obj.error("tradeoff", 'minimize = "failure-probability" with tradeoff (the table of the two '
                      "objectives)", raw_got=f"tradeoff = {describe(obj.raw('tradeoff'))}")
        tradeoff = obj.number("tradeoff", 5, integer=True, lo=2, hi=MAX_TRADEOFF)
    raw_tolerance = root.data.get("tolerance")
    given_bad = isinstance(raw_tolerance, dict) and "allowed_error" in raw_tolerance  # its own line says so
    if minimize is not None and (meta.tolerance is None or meta.tolerance.allowed_error is None) and not given_bad:
        where = "objective" if meta.tolerance is None else "tolerance"
        root.reader.error((where, "minimize") if where == "objective" else ("tolerance",),
                          "a [tolerance] table with allowed_error (the failure probability minimized is "
                          "that of P's error beyond it)", raw_got="none" if meta.tolerance is None
                          else "no allowed_error")
        minimize = None if meta.tolerance is None else minimize
    con = root.table("constraints")
    modes = _modes(con)
    branch = con.string("branch", "either", choices=SIDES + ("either",)) if con is not None else "either"
    floor, floor_ok = _floor(con, maximize or "conditioning", u)
    if meta.solver.method not in FiveBarPathProblem.methods:
        root.reader.error(("solver", "method"), 'method = "auto" for a five-bar (its one search: seeded '
                          "differential evolution, then Newton on the optimum's KKT conditions)",
                          raw_got=f'"{meta.solver.method}"')
        return None
    if (points is None or None in lengths.values() or gp is None or ga is None or maximize is None
            or modes is None or branch is None or not floor_ok or tradeoff is None):
        return None
    bounds = dict(lengths)
    bounds.update(pivot_x=gp[0], pivot_y=gp[1], ground_angle=ga)
    if len(points) > MAX_ROWS:  # pairs() bounds it already
        return None
    lines = {".".join(k): root.reader.line_of(k) for k in (("target", "points"), ("bounds",), ("constraints",))}
    return FiveBarPathProblem(meta=meta, points=tuple(points), bounds=bounds, modes=modes, branch=branch,
                              maximize=maximize, floor=floor, minimize=minimize, tradeoff=tradeoff or 5,
                              lines=lines)
