"""[tolerance] of a problem file (reading.meta.read_tolerance, reading.tolerance_keys): the tolerances,
clearances, cost models and schemes of a Monte Carlo precision study."""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class CostModel:
    """A cost-tolerance model c(t) of one toleranced dimension ([tolerance.cost];
    analysis.cost_models): `model` reciprocal | reciprocal-power | exponential |
    michael-siddall, its constants a, b, k, and the tolerances a process can hold
    (`bounds`, length unit; None where the file gives none)."""

    model: str
    a: float
    b: float
    k: float
    bounds: tuple[float, float] | None = None


@dataclass(frozen=True)
class CostSpec:
    """[tolerance.cost]: one model for every dimension (`default`) and per-key ones (`own`:
    a link, `coupler_point`, or a joint, whose fit's hole and shaft it prices)."""

    default: CostModel | None
    own: dict = field(default_factory=dict)

    def of(self, key: str) -> CostModel | None:
        return self.own.get(key, self.default)


@dataclass(frozen=True)
class Scheme:
    """One of [[tolerance.schemes]]: a named set of fits (joint -> "H7/g6") and length
    tolerances (key -> +- number, or `general`: key -> ISO 2768 class letter)."""

    name: str
    fits: dict
    lengths: dict
    general: dict = field(default_factory=dict)


@dataclass(frozen=True)
class Tolerance:
    """[tolerance]: manufacturing tolerances for a Monte Carlo precision study."""

    lengths: dict  # link name -> +- tolerance in the length unit (all four links present)
    distribution: str = "uniform"  # or "normal" (tolerance = 3 sigma)
    clearance: float = 0.0  # radial joint clearance, length unit
    clearance_slider: float = 0.0  # slider-crank: radial play of the slider in its guide, length unit
    lock_play: float = 0.0  # five-bar: +- angular play of a held drive's lock, rad
    samples: int = 20000
    allowed_error: float | None = None  # radians for angle errors, length unit for paths
    lines: dict = field(default_factory=dict, compare=False)  # key ("lengths.input") -> line, for messages
    general: dict = field(default_factory=dict)  # key -> ISO 2768-1 class ("m"): its general tolerance
    clearance_fits: bool = False  # clearance = "fits": each pin's play from its [joints] fit
    cost: CostSpec | None = None  # [tolerance.cost]: least-cost allocation
    schemes: tuple = ()  # [[tolerance.schemes]]: Scheme records to compare
    every: float | str | None = None  # a file that names no links ([linkage] topology: each design's are
    # its own): `lengths` as written, a tolerance or an ISO 2768 class for every link (`for_links`)


def for_links(tol, names):
    """`tol` with its `every` tolerance (or class) on each of `names` (a design's links, and
    "ground"), as `lengths` written as one number gives every link of a file that names them;
    `tol` itself when it has none."""
    from dataclasses import replace
    if tol is None or tol.every is None:
        return tol
    if isinstance(tol.every, str):
        return replace(tol, lengths={k: 0.0 for k in names}, general={k: tol.every for k in names}, every=None)
    return replace(tol, lengths={k: float(tol.every) for k in names}, every=None)


@dataclass(frozen=True)
class InverseTolerance(Tolerance):
    """[tolerance] with `max_failure_probability`: also find the largest tolerance, the
    same on every link, whose failure probability stays at or below that level."""

    max_failure_probability: float = 0.01
    lengths_given: bool = False  # `lengths` written in the file (0 included): the study uses it
