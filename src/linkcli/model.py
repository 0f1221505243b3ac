"""Frozen dataclasses: units, the four-bar, and one class per problem type (a tagged union).

Inside, lengths are in the file's length unit and angles in radians; `Units` converts
angles back for output. Problem classes hold validated data only: no numerics here.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from linkcli.units import Units

LINKS = ("ground", "input", "coupler", "output")
BRANCHES = ("open", "crossed")


@dataclass(frozen=True)
class SolverOptions:
    method: str = "auto"
    seed: int = 0
    budget: int | None = None


@dataclass(frozen=True)
class Reference:
    objective: float
    source: str | None = None


@dataclass(frozen=True)
class Tolerance:
    """[tolerance]: manufacturing tolerances for a Monte Carlo precision study."""

    lengths: dict  # link name -> +- tolerance in the length unit (all four links present)
    distribution: str = "uniform"  # or "normal" (tolerance = 3 sigma)
    clearance: float = 0.0  # radial joint clearance, length unit
    samples: int = 20000
    allowed_error: float | None = None  # radians for angle errors, length unit for paths


@dataclass(frozen=True)
class Meta:
    """What every problem file has: where it came from and how to solve and report it."""

    path: str
    type: str
    title: str | None = None
    units: Units = field(default_factory=Units)
    solver: SolverOptions = field(default_factory=SolverOptions)
    sections: tuple[str, ...] = ()
    reference: Reference | None = None
    tolerance: Tolerance | None = None


@dataclass(frozen=True)
class FourBar:
    """A planar four-bar (SPEC section 1). Lengths in the length unit, angles in radians."""

    ground: float
    input: float
    coupler: float
    output: float
    branch: str = "open"
    coupler_point: tuple[float, float] | None = None
    ground_pivot: tuple[float, float] = (0.0, 0.0)
    ground_angle: float = 0.0

    @property
    def abcd(self) -> tuple[float, float, float, float]:
        """Seed-paper letters: a = input, b = coupler, c = output, d = ground."""
        return (self.input, self.coupler, self.output, self.ground)


@dataclass(frozen=True)
class PrecisionPositionProblem:
    """Freudenstein function generation through paired (phi_i, psi_i) positions."""

    meta: Meta
    ground: float
    input_angles: tuple[float, ...]
    output_angles: tuple[float, ...]
    lines: tuple[int | None, ...] = ()  # line of each position pair, for messages


@dataclass(frozen=True)
class LinkageProblem:
    """Analysis of a given four-bar driven at a constant input speed."""

    meta: Meta
    linkage: FourBar
    input_speed: float = 1.0  # rad/s
    steps: int = 360


@dataclass(frozen=True)
class InverseTolerance(Tolerance):
    """[tolerance] with `max_failure_probability`: also find the largest tolerance, the
    same on every link, whose failure probability stays at or below that level."""

    max_failure_probability: float = 0.01
