"""[loads] and [masses] of a problem file (reading.loads, docs/loads.md): what the `forces`
section needs."""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class LinkMass:
    """A link's mass (kg), its centre in the link's own frame (input: origin A0, x to A;
    coupler: origin A, x to B; output: origin B0, x to B), inertia about it (kg m^2).
    In a problem the centre is in the file's length unit; the loads analysis takes metres.
    A slider (slider-crank) translates with B: only its mass counts."""

    mass: float
    center: tuple[float, float] = (0.0, 0.0)
    inertia: float = 0.0

    def __post_init__(self) -> None:
        if not (self.mass >= 0 and self.inertia >= 0):
            raise ValueError(f"mass and inertia must be >= 0, got {self.mass}, {self.inertia}")


@dataclass(frozen=True)
class Masses:
    """Mass properties per link; None is massless. Slider-crank: `output` is the slider.
    A drawn linkage names its own bodies: `named` holds (link or slider joint, LinkMass)
    pairs in file order (the three fields stay None)."""

    input: LinkMass | None = None
    coupler: LinkMass | None = None
    output: LinkMass | None = None
    named: tuple[tuple[str, LinkMass], ...] = ()

    def of(self, name: str) -> LinkMass | None:
        """The named body's mass (a drawn linkage's link or slider block), None if massless."""
        return dict(self.named).get(name)


@dataclass(frozen=True)
class Loads:
    """External loads, constant over the motion (SI, global frame).

    coupler_force: (Fx, Fy) N at the coupler point; output_torque: N m on the output link
    (four-bar, CCW +); output_force: N on the slider along +x (slider-crank);
    gravity: (gx, gy) m/s^2 acting on the masses. A drawn linkage names where its loads act:
    torques ((link, N m CCW +), ...) and forces ((joint, (Fx, Fy) N), ...), in file order.
    """

    coupler_force: tuple[float, float] = (0.0, 0.0)
    output_torque: float = 0.0
    output_force: float = 0.0
    gravity: tuple[float, float] = (0.0, 0.0)
    torques: tuple[tuple[str, float], ...] = ()
    forces: tuple[tuple[str, tuple[float, float]], ...] = ()


@dataclass(frozen=True)
class LoadCase:
    """[loads] and [masses] of a problem (docs/loads.md): what the `forces` section needs.
    Mass centres are in the file's length unit; `given` holds the keys as written (for the
    report's echo, so that a result file round-trips through `analyze`)."""

    loads: Loads = field(default_factory=Loads)
    masses: Masses = field(default_factory=Masses)
    given: dict = field(default_factory=dict, compare=False)
