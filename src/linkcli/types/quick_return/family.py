"""quick-return families: every linkage meeting a time ratio and a swing (or stroke) exactly,
and the member whose worst transmission angle over the full turn is best (radians throughout).

Crank-rocker: free parameter rho = +-(b - a) / |B1 B2| (geometry.py): the folded dead-centre
distance |A0 B2| over the chord of the rocker's extreme pins, negative when the crank pivot A0
lies on the rocker pivot's side of that chord. Its valid set is one or two open intervals
(geometry.valid_intervals): ends at rho = 0 (A0 on B2, a = b), where A0, B0 and B1 or B2 are
collinear (a Grashof change point: worst transmission 0), or at 1 / (2 sin(theta/2)) (a = 0).
K = 1 (theta = 0): rho in (0, inf), A0 on the line B1 B2 beyond B2; the worst transmission
rises towards 90 deg - swing/2 as A0 goes to infinity (centred in-line design: b, d -> inf,
a = c sin(swing/2)), so the best lies at infinity.
Slider-crank: free parameter rho = (b - a) / stroke in (0, cot(theta)), offset e >= 0 (the
mirror -e is the same design run backwards); a given offset fixes the design in closed form.

Where the best lies at infinity or the family reaches degenerate links, it is limited by
`bounds` ({"parameter" | "input" | "coupler" | "output" | "ground" | "offset": (lo, hi)},
the file's length unit) and always by MAX_LINK_RATIO: longest over shortest link <= 1e3
(a linkage beyond that is a drawing, not a machine; the project reader accepts up to 1e6, where
double precision still resolves the angles). A result on such a boundary says `limited`.

The search runs in v = |rho| / (1 + |rho|) in (0, 1) (maps infinite K = 1 ranges to a finite
one); maximize.maximize_min finds the global maximum of the worst transmission to full
precision (scan of 4096 points + bisection/golden refinement of every local maximum).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from linkcli.errors import SchemaError

from . import geometry, maximize, transmission

MAX_LINK_RATIO = 1e3
FOUR_BAR = ("input", "coupler", "output", "ground")
SLIDER = ("input", "coupler", "offset")
TABLE_ROWS = 21


@dataclass(frozen=True)
class Design:
    """One member: its parameter, lengths (file unit), worst transmission angle (rad)."""
    mechanism: str                      # "crank-rocker" | "slider-crank"
    parameter: float                    # rho (see module docstring)
    lengths: dict[str, float]           # input, coupler, output, ground | input, coupler, offset
    worst_transmission: float           # rad
    limited: bool = False               # on a bounds / link-ratio boundary
    parameter_ranges: tuple = field(default=())  # valid rho intervals of the whole family


# ---- input checks ---------------------------------------------------------------------------

def _theta(time_ratio: float) -> float:
    if not (np.isfinite(time_ratio) and time_ratio >= 1.0):
        raise SchemaError("a time ratio >= 1 (slow stroke over fast stroke)", f"{time_ratio!r}",
                          key="time_ratio")
    return geometry.dead_centre_angle(time_ratio)


def _swing(swing: float) -> float:
    if not (np.isfinite(swing) and 0.0 < swing < np.pi):
        raise SchemaError("a swing strictly between 0 and 180 deg",
                          f"{np.degrees(swing):g} deg", key="swing")
    return float(swing)


def _positive(value: float, key: str) -> float:
    if not (np.isfinite(value) and value > 0.0):
        raise SchemaError("a positive length", f"{value!r}", key=key)
    return float(value)


def _scale(scale) -> tuple[str, float]:
    name, value = scale
    if name not in ("ground", "output"):
        raise SchemaError("the scale: linkage.ground or linkage.output", str(name), key="linkage")
    return name, _positive(value, f"linkage.{name}")


# ---- crank-rocker ----------------------------------------------------------------------------

def crank_rocker_member(param, time_ratio: float, swing: float, scale) -> dict[str, np.ndarray]:
    """Lengths {input, coupler, output, ground} and worst_transmission (rad) of the members at
    rho = param (vectorized); scale = ("ground" | "output", length). Not checked for validity:
    see crank_rocker_ranges."""
    theta, swing = _theta(time_ratio), _swing(swing)
    name, value = _scale(scale)
    a, b, c, d, _, _ = geometry.crank_rocker_unit(param, theta, swing)
    k = value / (d if name == "ground" else c)
    out = {"input": a * k, "coupler": b * k, "output": c * k, "ground": d * k}
    out["worst_transmission"] = transmission.four_bar_worst(a, b, c, d)
    return out


def crank_rocker_ranges(time_ratio: float, swing: float) -> list[tuple[float, float]]:
    """The open rho intervals of the family; SchemaError when K and swing admit no
    crank-rocker."""
    theta, swing = _theta(time_ratio), _swing(swing)
    ranges = geometry.valid_intervals(theta, swing)
    if not ranges:
        raise SchemaError("a time ratio and swing that some crank-rocker meets",
                          f"time_ratio {time_ratio:g} with swing {np.degrees(swing):g} deg",
                          key="time_ratio")
    return ranges


def _to_rho(v, sign):
    v = np.asarray(v, dtype=float)
    with np.errstate(divide="ignore"):
        return sign * v / (1.0 - v)


def _to_v(rho):
    return np.inf if np.isinf(rho) else abs(rho) / (1.0 + abs(rho))


def _pieces(ranges):
    """(sign, v_lo, v_hi) per rho interval."""
    for lo, hi in ranges:
        sign = -1.0 if hi <= 0.0 else 1.0
        ends = sorted((abs(lo), abs(hi)))
        yield sign, _to_v(ends[0]) if ends[0] < np.inf else 1.0, \
            1.0 if ends[1] == np.inf else _to_v(ends[1])


def _feasible(lengths_of, names, bounds, max_ratio, sign, accept=None):
    """feasible(v): finite positive links within max_ratio, inside `bounds`, and (when
    given) accept(lengths) (e.g. the transmission window met)."""
    bounds = dict(bounds or {})
    unknown = set(bounds) - set(names) - {"parameter"}
    if unknown:
        raise SchemaError(f"bounds on {', '.join(('parameter',) + names)}",
                          ", ".join(sorted(unknown)), key="bounds")

    def feasible(v):
        rho = _to_rho(v, sign)
        lengths = lengths_of(rho)
        links = np.stack([np.abs(lengths[n]) for n in names if n != "offset"])
        ok = np.all(np.isfinite(links), axis=0) & (links.min(axis=0) > 0)
        with np.errstate(divide="ignore", invalid="ignore"):
            ok &= links.max(axis=0) <= max_ratio * links.min(axis=0)
        for key, (lo, hi) in bounds.items():
            val = rho if key == "parameter" else lengths[key]
            ok &= (val >= lo) & (val <= hi)
        if accept is not None:
            ok &= accept(lengths)
        return ok
    return feasible


def _search(lengths_of, margins_of, names, ranges, bounds, max_ratio, accept=None):
    """Best (value, rho, limited) over all pieces, or None when nothing is feasible."""
    best = None
    for sign, v_lo, v_hi in _pieces(ranges):
        feasible = _feasible(lengths_of, names, bounds, max_ratio, sign, accept)
        parts = (lambda s: lambda v: margins_of(lengths_of(_to_rho(v, s))))(sign)
        opt = maximize.maximize_min(parts, v_lo, v_hi, feasible)
        if opt is None:
            continue
        cand = (opt.value, float(_to_rho(opt.x, sign)), opt.limited)
        if best is None or cand[0] > best[0] + 1e-13 * max(1.0, abs(best[0])):
            best = cand
    return best


def _no_member(bounds):
    if bounds:
        return SchemaError("bounds that admit a member of the family", str(dict(bounds)),
                           key="bounds")
    return SchemaError(f"a family with longest/shortest link <= {MAX_LINK_RATIO:g}",
                       "none (swing or time ratio too extreme)", key="swing")


def _counted(lengths_of, counter):
    """lengths_of that adds the members it evaluates to `counter` (a search.budget.Budget)."""
    if counter is None:
        return lengths_of

    def counted(rho):
        counter.add(np.size(rho))
        return lengths_of(rho)
    return counted


def _within(margins_of, window):
    """accept(lengths): the whole turn inside the transmission window (None: no window)."""
    if window is None:
        return None
    return lambda lengths: np.min(margins_of(lengths, tuple(window)), axis=0) >= 0.0


def _crank_rocker_pieces(time_ratio, swing, scale, counter=None):
    ranges = crank_rocker_ranges(time_ratio, swing)

    def member(rho):
        return crank_rocker_member(rho, time_ratio, swing, scale)
    lengths_of = _counted(member, counter)

    def margins_of(lengths, window=(0.0, np.pi)):
        return transmission.four_bar_margins(lengths["input"], lengths["coupler"],
                                             lengths["output"], lengths["ground"], window)
    return ranges, lengths_of, margins_of


def best_crank_rocker(time_ratio: float, swing: float, scale, bounds: Mapping | None = None,
                      max_ratio: float = MAX_LINK_RATIO, window=None, counter=None) -> Design | None:
    """The member with the best worst transmission angle over the full turn; with a
    transmission `window` (lo, hi) (rad), the best among the members that keep the whole
    turn inside it (None when none does). `counter` counts the members evaluated."""
    ranges, lengths_of, margins_of = _crank_rocker_pieces(time_ratio, swing, scale, counter)
    best = _search(lengths_of, margins_of, FOUR_BAR, ranges, bounds, max_ratio,
                   _within(margins_of, window))
    if best is None and window is not None:
        return None  # closest_crank_rocker says by how much (or that no member exists at all)
    if best is None:
        raise _no_member(bounds)
    value, rho, limited = best
    member = lengths_of(rho)
    return Design("crank-rocker", rho, {n: float(member[n]) for n in FOUR_BAR},
                  float(member["worst_transmission"]), limited, tuple(ranges))


def _table(lengths_of, names, ranges, bounds, max_ratio, rows):
    runs = []
    for sign, v_lo, v_hi in _pieces(ranges):
        feasible = _feasible(lengths_of, names, bounds, max_ratio, sign)
        runs += [(sign, lo, hi) for lo, hi in maximize.feasible_runs(v_lo, v_hi, feasible)]
    if not runs:
        raise _no_member(bounds)
    total = sum(hi - lo for _, lo, hi in runs)
    rhos = []
    for sign, lo, hi in runs:
        m = max(2, int(round(rows * (hi - lo) / total)))
        rhos.append(_to_rho(lo + (hi - lo) * (np.arange(m) + 0.5) / m, sign))
    rho = np.sort(np.concatenate(rhos))
    out = lengths_of(rho)
    return {"parameter": rho, **{n: np.asarray(out[n]) for n in names},
            "worst_transmission": np.asarray(out["worst_transmission"])}


def crank_rocker_family(time_ratio: float, swing: float, scale, rows: int = TABLE_ROWS,
                        bounds: Mapping | None = None,
                        max_ratio: float = MAX_LINK_RATIO) -> dict[str, np.ndarray]:
    """About `rows` members spread over the feasible family (uniform in |rho|/(1+|rho|)):
    columns parameter, input, coupler, output, ground, worst_transmission; sorted by rho."""
    ranges, lengths_of, _ = _crank_rocker_pieces(time_ratio, swing, scale)
    return _table(lengths_of, FOUR_BAR, ranges, bounds, max_ratio, rows)


def closest_crank_rocker(time_ratio: float, swing: float, scale, window,
                         bounds: Mapping | None = None, max_ratio: float = MAX_LINK_RATIO,
                         counter=None) -> tuple[Design, float]:
    """(member, miss): the member whose transmission angle over the whole turn comes
    closest to the window (lo, hi) (rad), and by how much it leaves it (0: inside)."""
    ranges, lengths_of, margins_of = _crank_rocker_pieces(time_ratio, swing, scale, counter)
    best = _search(lengths_of, lambda m: margins_of(m, tuple(window)), FOUR_BAR, ranges,
                   bounds, max_ratio)
    if best is None:
        raise _no_member(bounds)
    value, rho, limited = best
    member = lengths_of(rho)
    return (Design("crank-rocker", rho, {n: float(member[n]) for n in FOUR_BAR},
                   float(member["worst_transmission"]), limited, tuple(ranges)),
            max(0.0, -value))


def crank_rocker_window_miss(time_ratio: float, swing: float, scale, window,
                             bounds: Mapping | None = None,
                             max_ratio: float = MAX_LINK_RATIO) -> float:
    """0 when some member keeps the transmission angle within window = (lo, hi) (rad) over
    the whole turn, else the smallest amount (rad) by which the members miss it."""
    return closest_crank_rocker(time_ratio, swing, scale, window, bounds, max_ratio)[1]


# ---- slider-crank ----------------------------------------------------------------------------

def _slider_theta(time_ratio: float) -> float:
    theta = _theta(time_ratio)
    if theta >= 0.5 * np.pi:
        raise SchemaError("a time ratio below 3 for a slider-crank (dead-centre angle < 90 deg)",
                          f"{time_ratio:g}", key="time_ratio")
    return theta


def slider_crank_member(param, time_ratio: float, stroke: float) -> dict[str, np.ndarray]:
    """Lengths {input, coupler, offset} and worst_transmission (rad) at rho = (b - a)/stroke
    (vectorized; the offset is >= 0)."""
    theta, stroke = _slider_theta(time_ratio), _positive(stroke, "stroke")
    a, b, e = geometry.slider_crank_unit(param, theta, stroke)
    return {"input": a, "coupler": b, "offset": e,
            "worst_transmission": transmission.slider_extremes(a, b, e)[0]}


def slider_crank_ranges(time_ratio: float) -> list[tuple[float, float]]:
    """[(0, cot(theta))], or [(0, inf)] for K = 1."""
    return [(0.0, geometry.slider_rho_max(_slider_theta(time_ratio)))]


def slider_crank_with_offset(time_ratio: float, stroke: float, offset: float) -> Design:
    """The unique slider-crank of stroke H, time ratio K and offset e (closed form; the sign
    of e is kept). K = 1 with e = 0 is a family (use best_slider_crank)."""
    theta, stroke = _slider_theta(time_ratio), _positive(stroke, "stroke")
    if not np.isfinite(offset):
        raise SchemaError("a finite offset", f"{offset!r}", key="linkage.offset")
    limit = stroke * np.cos(theta) / np.sin(theta) if theta > 0 else 0.0
    if theta == 0.0 and offset != 0.0:
        raise SchemaError("offset 0 (time ratio 1 needs an in-line slider-crank)",
                          f"{offset:g}", key="linkage.offset")
    if theta > 0.0 and offset == 0.0:
        raise SchemaError("a nonzero offset (an in-line slider-crank has time ratio 1)",
                          "0", key="linkage.offset")
    if abs(offset) >= limit:
        raise SchemaError(f"an offset of magnitude below stroke * cot(theta) = {limit:.6g} "
                          f"for stroke {stroke:g} and time ratio {time_ratio:g}",
                          f"{offset:g}", key="linkage.offset")
    a, b = geometry.slider_crank_with_offset(stroke, theta, offset)
    return Design("slider-crank", (b - a) / stroke, {"input": a, "coupler": b, "offset": offset},
                  float(transmission.slider_extremes(a, b, offset)[0]), False,
                  tuple(slider_crank_ranges(time_ratio)))


def _slider_pieces(time_ratio, stroke, counter=None):
    ranges = slider_crank_ranges(time_ratio)

    def member(rho):
        return slider_crank_member(rho, time_ratio, stroke)
    lengths_of = _counted(member, counter)

    def margins_of(lengths, window=(0.0, np.pi)):
        return transmission.slider_margins(lengths["input"], lengths["coupler"],
                                           lengths["offset"], window)
    return ranges, lengths_of, margins_of


def _slider_design(lengths_of, ranges, best) -> Design:
    value, rho, limited = best
    member = lengths_of(rho)
    return Design("slider-crank", rho, {n: float(member[n]) for n in SLIDER},
                  float(member["worst_transmission"]), limited, tuple(ranges))


def best_slider_crank(time_ratio: float, stroke: float, bounds: Mapping | None = None,
                      max_ratio: float = MAX_LINK_RATIO, window=None,
                      counter=None) -> Design | None:
    """The free-offset member with the best worst transmission angle (offset >= 0); with a
    `window`, the best among the members inside it (None when none is)."""
    ranges, lengths_of, margins_of = _slider_pieces(time_ratio, stroke, counter)
    best = _search(lengths_of, margins_of, SLIDER, ranges, bounds, max_ratio,
                   _within(margins_of, window))
    if best is None and window is not None:
        return None
    if best is None:
        raise _no_member(bounds)
    return _slider_design(lengths_of, ranges, best)


def slider_crank_family(time_ratio: float, stroke: float, rows: int = TABLE_ROWS,
                        bounds: Mapping | None = None,
                        max_ratio: float = MAX_LINK_RATIO) -> dict[str, np.ndarray]:
    """About `rows` members of the free-offset family: parameter, input, coupler, offset,
    worst_transmission."""
    ranges, lengths_of, _ = _slider_pieces(time_ratio, stroke)
    return _table(lengths_of, SLIDER, ranges, bounds, max_ratio, rows)


def closest_slider_crank(time_ratio: float, stroke: float, window, bounds: Mapping | None = None,
                         max_ratio: float = MAX_LINK_RATIO, counter=None) -> tuple[Design, float]:
    """(member, miss) of the free-offset family, as closest_crank_rocker."""
    ranges, lengths_of, margins_of = _slider_pieces(time_ratio, stroke, counter)
    best = _search(lengths_of, lambda m: margins_of(m, tuple(window)), SLIDER, ranges,
                   bounds, max_ratio)
    if best is None:
        raise _no_member(bounds)
    return _slider_design(lengths_of, ranges, best), max(0.0, -best[0])


def slider_window_miss(design: Design, window) -> float:
    """How far (rad) one slider-crank's transmission angle leaves the window (0: inside)."""
    L = design.lengths
    m = transmission.slider_margins(L["input"], L["coupler"], L["offset"], tuple(window))
    return max(0.0, -float(np.min(m)))


def slider_crank_window_miss(time_ratio: float, stroke: float, window,
                             offset: float | None = None, bounds: Mapping | None = None,
                             max_ratio: float = MAX_LINK_RATIO) -> float:
    """As crank_rocker_window_miss; with a given offset, the miss of that unique design."""
    if offset is not None and not (offset == 0.0 and _theta(time_ratio) == 0.0):
        return slider_window_miss(slider_crank_with_offset(time_ratio, stroke, offset), window)
    return closest_slider_crank(time_ratio, stroke, window, bounds, max_ratio)[1]
