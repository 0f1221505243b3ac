"""[sections], [material] and [strength] of a problem file (reading.strength, docs/strength.md)."""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class LinkSection:
    """A link's cross-section ([sections], docs/strength.md), length unit: a `rectangle`
    (`width` in the plane of motion, `thickness` normal to it), a `round` bar (`diameter`) or
    a `tube` (outer `diameter`, `wall`)."""

    shape: str
    width: float | None = None
    thickness: float | None = None
    diameter: float | None = None
    wall: float | None = None
    line: int | None = None

    @property
    def plane_width(self) -> float | None:
        """The width in the plane of motion: a rectangle's `width`, a round bar's or tube's
        outer `diameter` (what a drawing's outline shows)."""
        return self.width if self.shape == "rectangle" else self.diameter


@dataclass(frozen=True)
class StrengthSpec:
    """[material] and [strength] (docs/strength.md): the strengths in MPa (`yield_`: the
    tensile yield strength; `endurance`: fully reversed; `modulus`: Young's), the material's
    listed `name` and `source` when named, `endurance_listed` when the endurance is the list's
    uncorrected specimen value; the `required` safety factor and the fatigue `criterion`."""

    ultimate: float
    yield_: float
    endurance: float
    modulus: float
    name: str | None = None
    source: str | None = None
    endurance_listed: bool = False
    required: float = 1.0
    criterion: str = "goodman"
    lines: dict = field(default_factory=dict, compare=False)  # table name -> line, for messages
