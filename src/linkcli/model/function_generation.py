"""A function-generation problem (types.function_generation)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar


@dataclass(frozen=True)
class FunctionGenerationProblem:
    """Function generation by optimization: free lengths (and start angles) such that the
    output angle psi follows a law over the input sweep (docs/format.md).

    Two forms: `form = "output"`, psi = law(phi, phi0, psi0) with phi from phi0 to
    phi0 + input_sweep; `form = "function"`, y = f(x) mapped linearly onto the input and
    output sweeps (`shape` holds (f(x_k) - f(x0)) / (f(x1) - f(x0)) at each point).
    The evaluation points sit at phi_k = phi0 + fractions[k] * input_sweep.
    """

    mechanism: ClassVar[str] = "four-bar"  # the mechanism designed (its home's synthesis face)
    meta: Meta
    fixed: dict  # link -> length held fixed (at least one: it sets the scale)
    bounds: dict  # link -> (lo, hi) of each free length
    law: object  # expr.Expression: psi(phi, phi0, psi0) or f(x), radians
    form: str  # "output" or "function"
    input_sweep: float  # signed, rad (negative: clockwise)
    fractions: tuple[float, ...]  # position of each evaluation point along the sweep, [0, 1]
    start: str = "given"  # "extended": phi0, psi0 at the extended dead-centre; "given"
    input_start: float | None = None  # rad, when given in [target]
    output_start: float | None = None  # rad, when given in [target]
    start_bounds: dict = field(default_factory=dict)  # "input_start"/"output_start" -> (lo, hi) rad
    output_sweep: float | None = None  # function form: signed, rad
    x_range: tuple[float, float] | None = None  # function form: (x0, x1)
    shape: tuple[float, ...] = ()  # function form: normalized f at each evaluation point
    spacing: str = "uniform"  # "uniform" (ends included) or "chebyshev" (ends excluded)
    transmission: tuple[float, float] | None = None  # window on mu, rad
    grashof: str = "any"  # a class of mechanisms.four_bar.kinematics.GRASHOF_CLASSES (not change-point) or "any"
    branch: str = "either"  # "open", "crossed" or "either"
    lines: dict = field(default_factory=dict)  # key -> line of the file, for messages
    objective: str = "error"  # [objective] minimize: "error" or "failure-probability" (robust design)
    defect_free: float = 0.99  # [constraints] defect_free: least share of made linkages that assemble
