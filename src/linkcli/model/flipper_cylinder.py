"""A flipper-cylinder problem (types.flipper_cylinder)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class FlipperCylinderProblem:
    """A hydraulic cylinder turning a loaded platform about its hinge B = (0, 0).

    The rod pivot A and the centre of mass are given in the platform frame at the start
    position and turn with the platform, X(t) = R(t - start) X_start; the base pivot C is
    fixed. Pivot bounds are ((x_lo, x_hi), (y_lo, y_hi)); lo == hi fixes a coordinate.
    """

    meta: Meta
    mass: float  # kg, platform plus payload
    center_of_mass: tuple[float, float]  # length unit, platform frame at the start position
    gravity: float  # m/s^2
    start: float  # rad, platform angle at the start of the sweep
    end: float  # rad, > start, end - start < pi (counter-clockwise)
    rod_pivot: tuple[tuple[float, float], tuple[float, float]]  # A at the start position
    base_pivot: tuple[tuple[float, float], tuple[float, float]]  # C, fixed to the base
    minimize: str = "peak-force"  # or "cylinder-length" (subject to max_force)
    bore: float | None = None  # length unit (push acts on the bore area)
    rod: float | None = None  # length unit (pull acts on the annulus bore - rod)
    dead_length: float | None = None  # length unit: closed length >= stroke + dead_length
    max_force: float | None = None  # N
    pareto: int = 0  # rows of the force/size trade-off table (0: none)
    table_step: float | None = None  # rad between rows of the force table; None: a round step
    # A clockwise sweep (end < start in the file) is held as its mirror image in the vertical
    # line through the hinge (x -> -x, angles -> -angles; gravity stays vertical, forces and
    # lengths are the same): start < end above, and `shown_angle`/`shown_x` give the file's
    # values back for every output.
    clockwise: bool = False

    def shown_angle(self, angle: float) -> float:
        """An internal angle (rad) as the file's sweep has it."""
        return -angle if self.clockwise else angle

    def shown_x(self, x: float) -> float:
        """An internal x coordinate as in the file's frame."""
        return -x if self.clockwise else x

    @property
    def bounds(self) -> tuple[tuple[float, float], ...]:
        """(lo, hi) of A_x, A_y, C_x, C_y."""
        return self.rod_pivot + self.base_pivot

    @property
    def fixed(self) -> bool:
        """Every pivot coordinate given as a number: the design is only evaluated."""
        return all(lo == hi for lo, hi in self.bounds)

    @property
    def methods(self) -> tuple[str, ...] | None:
        """The [solver] methods that change anything (bench's settings): a fixed design is
        evaluated, whatever the method; None: every method of the type."""
        return ("auto",) if self.fixed else None
