"""Frozen dataclasses: what every problem has, and one class per problem type (a tagged union).

Inside, lengths are in the file's length unit and angles in radians; `Units` converts
angles back for output. Problem classes hold validated data only: no numerics here.

What every problem has (Meta, its solver options, the `Linkage` protocol every mechanism's
record follows) is defined here; each mechanism's own record lives in its home
(`mechanisms/<home>/model.py`); the records of optional tables ([tolerance], [loads]/[masses], [sections]/
[material]) and each problem type's class live in a submodule of their own, made on first
use: `from linkcli.model import Tolerance` works as before, but a run that never touches
a tolerance does not pay for building its classes (each frozen dataclass compiles six
methods when defined, 0.5 to 1 ms apiece: the bulk of this package's import).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar, Protocol

from linkcli.units import Units

HOMES = {  # class -> the submodule of linkcli.model that defines it (imported on first use)
    **dict.fromkeys(("CostModel", "CostSpec", "Scheme", "Tolerance", "InverseTolerance"), "tolerance"),
    **dict.fromkeys(("LinkMass", "Masses", "Loads", "LoadCase"), "loads"),
    **dict.fromkeys(("LinkSection", "StrengthSpec"), "strength"),
    "PrecisionPositionProblem": "precision_position",
    "LinkageProblem": "linkage",
    "PathGenerationProblem": "path_generation",
    "MotionGenerationProblem": "motion_generation",
    "FunctionGenerationProblem": "function_generation",
    "FlipperCylinderProblem": "flipper_cylinder",
    "QuickReturnProblem": "quick_return",
    "DrawnDesignProblem": "drawn_design",
}


def __getattr__(name: str):
    """A class of HOMES, imported from its submodule on first use (PEP 562)."""
    home = HOMES.get(name)
    if home is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    import importlib
    value = getattr(importlib.import_module(f"{__name__}.{home}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(HOMES))


@dataclass(frozen=True)
class SolverOptions:
    method: str = "auto"
    seed: int = 0
    budget: int | None = None
    atlas: bool | None = None  # [solver] atlas (path generation, free timing): None = the default, on


@dataclass(frozen=True)
class Reference:
    objective: float
    source: str | None = None


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
    notes: tuple[str, ...] = ()  # notes on the file itself (angles that look like the other unit)
    loads: LoadCase | None = None  # [loads] / [masses]: the forces section
    joints: tuple = ()  # [joints]: io.joints.JointSpec per joint (part sizes, a drawing)
    link_sections: dict = field(default_factory=dict)  # [sections]: link -> LinkSection
    strength: StrengthSpec | None = None  # [material] / [strength]: the strength section
    dynamics: object = None  # [springs] / [dampers] / [dynamics]: model.dynamics.Dynamics


class Linkage(Protocol):
    """What every mechanism's linkage record is (each home defines its own frozen dataclass:
    mechanisms/<home>/model.py): it names its mechanism, whose home (linkcli.mechanisms) knows
    the rest."""

    mechanism: ClassVar[str]
