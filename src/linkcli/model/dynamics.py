"""[springs], [dampers] and [dynamics] as validated data (docs/dynamics.md). Pure Python: `check`
builds them without numpy.

Inside, lengths are in the file's length unit, angles in radians, speeds in rad/s (or length
unit per s), forces in N, torques in N m, times in s. A stiffness is N per length unit (linear)
or N m per rad (torsional); a damping coefficient N s per length unit or N m s per rad.
"""

from __future__ import annotations

from dataclasses import dataclass, field

LINEAR, TORSIONAL = "linear", "torsional"
FREE, TORQUE, MOTOR = "free", "torque", "motor"


@dataclass(frozen=True)
class End:
    """One end of a linear element: a named point of the linkage (`point`), or an anchor fixed
    to the ground at `at` (global frame, length unit)."""

    point: str | None = None
    at: tuple[float, float] | None = None


@dataclass(frozen=True)
class Spring:
    """A linear spring between two ends (tension F = preload + stiffness (L - free), pulling
    the ends together when positive), or a torsional spring on a link (about the ground) or
    between two links (torque -stiffness (theta - free) on `links[-1]`, the opposite on
    `links[0]` when there are two; theta the link's angle, or the second's minus the
    first's)."""

    name: str
    kind: str
    stiffness: float
    free: float
    ends: tuple[End, End] | None = None
    links: tuple[str, ...] = ()
    preload: float = 0.0


@dataclass(frozen=True)
class Damper:
    """A linear damper between two ends (force opposing the rate of change of their distance)
    or a rotary damper on a link or between two links (torque opposing the rate of its angle):
    `coefficient` (force = coefficient x rate), or `table` ((rate, force), ...) with rates
    strictly increasing (length unit/s or rad/s) and forces in N or N m (module docstring of
    dynamics.elements: interpolation and the mirrored half)."""

    name: str
    kind: str
    coefficient: float | None = None
    table: tuple[tuple[float, float], ...] | None = None
    ends: tuple[End, End] | None = None
    links: tuple[str, ...] = ()


@dataclass(frozen=True)
class Drive:
    """What turns the drive: nothing (`free`), a constant `torque` (N m), or a motor's
    `curve` ((speed rad/s, torque N m), ...), speeds strictly increasing."""

    kind: str = FREE
    torque: float = 0.0
    curve: tuple[tuple[float, float], ...] = ()


@dataclass(frozen=True)
class DriveSetup:
    """One drive of a linkage of several (each [dynamics] key by drive name: the five-bar's
    input and input2): its law, its start (angle rad, speed rad/s), the angle that stops the
    run, marks (angles whose crossings are events) and the inertia turning with it (kg m^2)."""

    name: str
    drive: Drive = field(default_factory=Drive)
    start: tuple[float, float] | None = None
    stop: float | None = None
    marks: tuple[float, ...] = ()
    flywheel_inertia: float = 0.0
    locked: bool = False  # held at its start angle (a brake): its speed stays 0, its torque is the reaction


@dataclass(frozen=True)
class Dynamics:
    """Everything [springs], [dampers] and [dynamics] ask for.

    The simulation runs when `start` is given: (angle rad, speed rad/s) of the drive; it ends
    at `stop` (an angle, rad) or after `duration` (s), with `steps` output points evenly
    spaced in time. `marks`: angles whose crossings are events. `friction`: Coulomb
    coefficient in every pin (radius from `pin_diameters`, length unit) and slider guide;
    `friction_speed` (rad/s) smooths its sign at rest. `dead_point` (rad): a closure's
    transmission angle this close to 0 or 180 deg ends the run. `flywheel_inertia` (kg m^2)
    turns with the drive. `fluctuation` (Cs) asks for the flywheel section, at the motor's
    mean speed or `mean_speed` (rad/s). `balance`: the shaking force and moment;
    `counterweights`: also the counterweights, at `counterweight_radii` (link -> length unit;
    a link not named: its own length). `lines`: key path -> line, for errors found when solved.

    A linkage of several drives holds each one's law, start, stop, marks and inertia in
    `drives` (DriveSetup, in the order of its drive values); the one-drive fields `drive`,
    `start`, `stop`, `marks` and `flywheel_inertia` are then unused (their defaults)."""

    springs: tuple[Spring, ...] = ()
    dampers: tuple[Damper, ...] = ()
    drive: Drive = field(default_factory=Drive)
    start: tuple[float, float] | None = None
    stop: float | None = None
    duration: float | None = None
    steps: int = 1000
    marks: tuple[float, ...] = ()
    friction: float = 0.0
    friction_speed: float = 1e-3
    pin_diameters: tuple[tuple[str, float], ...] = ()
    dead_point: float = 0.017453292519943295
    method: str = "auto"
    flywheel_inertia: float = 0.0
    fluctuation: float | None = None
    mean_speed: float | None = None
    balance: bool = False
    counterweights: bool = False
    counterweight_radii: tuple[tuple[str, float], ...] = ()
    drives: tuple[DriveSetup, ...] = ()
    lines: dict = field(default_factory=dict, compare=False)

    @property
    def simulates(self) -> bool:
        return self.start is not None or any(d.start is not None for d in self.drives)
