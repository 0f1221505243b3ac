"""A design problem on a drawn linkage (synthesis.schema): path, motion or
function generation with `[linkage] mechanism = "drawn"`."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar


@dataclass(frozen=True)
class DrawnDesignProblem:
    """A drawn linkage designed for a target (docs/drawn_synthesis.md).

    `drawing` is the starting design (mechanisms.drawn.model.Drawn): its topology, its drive
    and the place of every joint; `boxes` gives each free joint's box ((x lo, x hi), (y lo,
    y hi)), in the order of [bounds] (the design variables). Drive angles are offsets from
    the drawn position of the driving link (rad, 0 = as drawn), link angles offsets from the
    link's drawn angle.

    kind "path": `joint` through `points` (global frame); "motion": the frame of `link`
    (origin at its first listed joint, x axis towards its second) through `poses` (x, y,
    angle rad), `angle_weight` a length (None: the poses' characteristic length); "function":
    the angle of `link` following `law` (expr.Expression) over the drive's sweep, in
    function generation's two forms (`form` "output": psi = law(phi, phi0, psi0), "function":
    psi = psi0 + shape_k output_sweep), the sweep phi_k = phi0 + fractions_k input_sweep;
    phi0 (`input_start`) and psi0 (`output_start`) given, or free within `start_bounds`.
    Path and motion: `timing` "prescribed" (`input_angles`, with `input_offset` bounds: one
    free angle added to all) or "free" (`direction`). `drive`: "crank" (the driving link
    turns fully with every closure closed) or "any" (it may rock: every closure closed from
    the drawn position through the targets); `transmission`: the window every closure's
    transmission angle keeps there (rad)."""

    mechanism: ClassVar[str] = "drawn"
    bench_settings: ClassVar[tuple] = (("auto", None),)  # `linkcli bench`: its one method, its budget
    meta: Meta
    kind: str
    drawing: object
    boxes: tuple  # ((joint, ((x lo, x hi), (y lo, y hi))), ...)
    joint: str | None = None
    link: str | None = None
    points: tuple = ()
    poses: tuple = ()
    angle_weight: float | None = None
    timing: str = "prescribed"
    input_angles: tuple | None = None
    input_offset: tuple[float, float] | None = None
    direction: str = "either"
    law: object = None
    form: str = "output"
    input_sweep: float = 0.0
    fractions: tuple = ()
    input_start: float | None = None
    output_start: float | None = None
    start_bounds: dict = field(default_factory=dict)
    output_sweep: float | None = None
    x_range: tuple | None = None
    shape: tuple = ()
    drive: str = "any"
    transmission: tuple[float, float] | None = None
    steps: int = 360
    lines: dict = field(default_factory=dict)
    objective: str = "error"
    defect_free: float = 0.99

    @property
    def free(self) -> tuple[str, ...]:
        return tuple(name for name, _ in self.boxes)
