"""The protocol every mechanism's home implements, and the records its methods return.

Shared code -- the report sections of analysis/, the loads, the tolerance Monte Carlo, the
plots, the animation and CAD writers -- holds a `Mechanism` (from `linkcli.mechanisms.of`)
and calls these methods; it never asks which mechanism it holds. A home lives in
`mechanisms/<name>/`: `kinematics.py` (closed forms, vectorized over angles and
populations), `schema.py` (its `[linkage]` keys), `home.py` (the `Mechanism` below),
and what else it needs (`sections.py`, `loads.py`, `tolerance.py`).

Angles are radians and lengths the file's length unit inside; section methods return
output-ready dicts (the file's units, round-off snapped to 0 under the noise floor of
`size()`), as the report prints them.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from linkcli.angles import wrap  # the one wrap

TWO_PI = 2.0 * np.pi


@dataclass(frozen=True)
class Study:
    """The range of the motion study: the drive turns fully, or rocks over `arc` = (lo, hi)
    with hi >= lo (rad, counter-clockwise from lo). `detail` is the home's own record of
    the range (a four-bar's `Motion`), passed back to its section methods."""

    full_turn: bool
    arc: tuple[float, float]
    detail: Any = None
    shortfall: str | None = None  # why the asked motion stops short of what was asked (exit 1)

    def rows(self, steps: int) -> tuple[np.ndarray, np.ndarray]:
        """(phi, shown): the drive angles (rad) of the study's rows and as printed. A full
        turn: phi = k 2 pi / steps from 0, shown 0 .. 360 deg; a rocking drive: the centres
        of `steps` equal cells of its arc (its ends are toggles, where a constant speed
        would need an infinite one elsewhere), shown wrapped to (-180, 180] deg. The
        kinematics and forces sections share these rows."""
        if self.full_turn:
            phi = np.arange(steps) * (TWO_PI / steps)
            return phi, phi
        lo, hi = self.arc
        phi = lo + (np.arange(steps) + 0.5) * ((hi - lo) / steps)
        return phi, wrap(phi)

    def printed(self, shown, units) -> np.ndarray:
        """The rows' drive values as the report prints them (the file's angle unit; a home
        whose drive slides prints lengths)."""
        return units.from_rad(np.asarray(shown, dtype=float))

    def unit(self, units) -> str:
        """The unit of the printed drive values."""
        return units.angle


@dataclass(frozen=True)
class Guide:
    """A straight slider guide fixed to the ground: through `point` at `angle` (rad),
    drawn over the travel of `joint`."""

    point: tuple[float, float]
    angle: float
    joint: str


@dataclass(frozen=True)
class Skeleton:
    """What a drawing needs at n rows, in the global frame (length unit).

    joints: name -> (n, 2) positions (NaN where the linkage does not assemble);
    links: name -> the joints it carries, in drawing order (a binary link is a bar, a
    ternary or larger one a plate); ground: the joints fixed to the ground (drawn as
    pivots); guides: slider guides; sliders: joints that slide on a guide (drawn as
    blocks); traced: the points whose paths a drawing follows (coupler point, output
    point); valid: (n,) the rows where it assembles."""

    joints: dict[str, np.ndarray]
    links: dict[str, tuple[str, ...]]
    ground: tuple[str, ...]
    valid: np.ndarray
    guides: tuple[Guide, ...] = ()
    sliders: tuple[str, ...] = ()
    traced: tuple[str, ...] = ()

    def size(self) -> float:
        """The largest extent of the joints over the rows: the drawing's length scale."""
        pts = np.concatenate([np.asarray(p, dtype=float).reshape(-1, 2) for p in self.joints.values()])
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        if not len(pts):
            return 1.0
        extent = float(np.max(pts.max(axis=0) - pts.min(axis=0)))
        return extent if extent > 0 else 1.0


@dataclass
class LoadRows:
    """Inverse dynamics at every row: input_torque (n,) N m (the drive's torque on its
    link, counter-clockwise positive); pins {name: (n, 2) N}, each the force the ground or
    the neighbouring link exerts at that joint (the home documents on which link);
    singular (n,) bool (a dead point: forces NaN); mechanical_advantage (n,) (NaN at a
    toggle: infinite; None for a linkage of several drives, which has no one mechanical
    advantage); force_scale (N) and torque_scale (N m) for the noise floor; pin_names in report
    order; other_drives: a linkage of several drives' other drives, name -> (its angle at each
    row as printed, rad, and its torque (n,) N m), reported as `<name>` and `<name>_torque`
    beside `input` and `input_torque` (the five-bar's input2)."""

    input_torque: np.ndarray
    pins: dict[str, np.ndarray]
    singular: np.ndarray
    mechanical_advantage: np.ndarray | None
    force_scale: float
    torque_scale: float
    pin_names: tuple[str, ...] = field(default=())
    other_drives: dict[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)

    def magnitude(self, pin: str) -> np.ndarray:
        return np.hypot(self.pins[pin][:, 0], self.pins[pin][:, 1])


@dataclass(frozen=True)
class LinkLoad:
    """One load on one link at every row (n rows), SI, global frame: `force` (n, 2) N acting
    ON the link at the point `at` (n, 2) m, and a `couple` (n,) N m on it (counter-clockwise
    positive). `name`: the joint it acts through (a pin force) or what it is (a home's word:
    "drive", "coupler_force", "output_torque", "inertia" -- weight and d'Alembert inertia of
    the link's mass at its centre, -m a_G + m g and -I_G alpha)."""

    name: str
    at: np.ndarray
    force: np.ndarray
    couple: np.ndarray


@dataclass(frozen=True)
class MemberForces:
    """What the strength section needs of a mechanism at the rows of a load study.

    links: link name (as [sections] names it) -> the joints at its ends, in order (a binary
    link: two joints; its axis runs from the first to the second). loads: link name -> every
    load on it, its joints' forces first (in the order of `links`, named by the joint), then
    what acts between or beside them (a coupler force, a drive or load torque, its mass's
    weight and inertia); together they are in equilibrium at every valid row (sum of forces
    and of moments 0: d'Alembert). pins: joint name (as [joints] names it) -> (n, 2) N, the
    shear force the pin carries (for two links joined, the force one exerts on the other);
    only revolute pins (a slider's guide is not one). not_bars: link name -> why a link of two
    joints is still no bar between two pins (a slider's guide: the block runs along it);
    strength lists it unchecked, as a plate of three or more joints."""

    links: dict[str, tuple[str, ...]]
    loads: dict[str, tuple[LinkLoad, ...]]
    pins: dict[str, np.ndarray]
    not_bars: dict[str, str] = field(default_factory=dict)


@dataclass(frozen=True)
class BodyGraph:
    """A linkage as rigid bodies joined by pins and guides, for its dynamics (linkcli.analysis.dynamics:
    the equations of motion, the pin forces under force elements, balancing). SI: lengths in m.

    bodies: the moving bodies in order (links by their [links]/[sections] names; a slider
    block by the name [masses] gives it); the ground is "ground". blocks: the bodies that only
    translate (slider blocks: a point mass at their frame's origin, the joint). masses: body
    -> LinkMass (centre in the body's own frame, m); a massless body is absent. points: name
    -> (body, (x, y) in its frame): every joint (and the coupler point), on the moving body a
    load at that point acts on ("ground" with global coordinates for a joint on the ground
    only). pins: (report name, joint, body exerting, body acted on), one per pair of bodies a
    revolute pin joins (its force is reported on the second, as the home's `load_rows`
    reports it). guides: (report name, joint, guide body, block, (ux, uy) the guide's
    direction in the guide body's frame). drive: the body the drive turns, whose frame angle
    is its drawn angle plus the drive value q. forces: constant [loads] forces (point, (Fx, Fy)
    N); couples: constant [loads] couples (body, N m); gravity (gx, gy) m/s^2. A linkage of
    several drives (k degrees of freedom, one drive value q_j each) lists them in `drives`,
    (name as [dynamics] names it, body it turns), `drive` being the first's body; `traced`:
    points whose path the history reports (the five-bar's P)."""

    bodies: tuple[str, ...]
    blocks: tuple[str, ...]
    masses: dict
    points: dict
    pins: tuple[tuple[str, str, str, str], ...]
    guides: tuple[tuple[str, str, str, str, tuple[float, float]], ...]
    drive: str
    forces: tuple[tuple[str, tuple[float, float]], ...] = ()
    couples: tuple[tuple[str, float], ...] = ()
    gravity: tuple[float, float] = (0.0, 0.0)
    drives: tuple[tuple[str, str], ...] = ()
    traced: tuple[str, ...] = ()

    @property
    def driven(self) -> tuple[tuple[str, str], ...]:
        """(drive name, body it turns) of every drive, in the order of the drive values q_j:
        `drives` when the linkage has several, else ((body, `drive`),) (its one drive)."""
        return self.drives or ((self.drive, self.drive),)


@dataclass(frozen=True)
class Coefficients:
    """The kinematic coefficients of a one-drive linkage at drive values q (n rows), SI: the
    velocity ratios of every body with respect to the drive value and their derivatives
    (Uicker, Pennock & Shigley, Theory of Machines and Mechanisms, ch. 4 and 16, kinematic
    coefficients; Paul, Kinematics and Dynamics of Planar Machinery, ch. 13). origin: body ->
    (x, dx/dq, d2x/dq2), each (n, 2) m, of the origin of its frame; angle: body -> (theta,
    dtheta/dq, d2theta/dq2), each (n,), its frame's angle (global, rad). A point l of a body:
    p = x + R(theta) l, p' = x' + theta' perp(R l), p'' = x'' + theta'' perp(R l) - theta'^2 R l.
    valid: (n,) bool, the rows where it assembles; lock: (n,) the smallest |sin| of a
    transmission angle over its closures (0 at a dead point, where the coefficients grow
    without bound).

    A linkage of k drives: q is (n, k), and each derivative gains an axis per drive: origin
    (x (n, 2), dx/dq_j (n, 2, k), d2x/dq_i dq_j (n, 2, k, k)), angle (theta (n,), (n, k),
    (n, k, k)). `watched`: name -> (n,) |sin| of an angle whose zero is a singularity the motion
    passes through (the run reports it, it does not end there: the five-bar's type I)."""

    q: np.ndarray
    origin: dict
    angle: dict
    valid: np.ndarray
    lock: np.ndarray
    watched: dict = field(default_factory=dict)

    @property
    def drives(self) -> int:
        """k, the number of drive values."""
        return 1 if np.ndim(self.q) == 1 else int(np.shape(self.q)[1])


@dataclass(frozen=True)
class PointCoefficients:
    """The kinematic coefficients of a linkage of k drives at one state q (k drive values), in
    Python floats: what the integrator's right-hand side reads at every step, where an array
    per step would cost more than the arithmetic. origin: body -> ((x, y), first, second),
    first[j] = (dx/dq_j, dy/dq_j), second[i][j] = the second partials d2/dq_i dq_j (pairs);
    angle: body -> (theta, first[j], second[i][j]); lock and watched as Coefficients' (floats);
    valid: the linkage assembles there (else the other fields may be empty)."""

    origin: dict
    angle: dict
    lock: float
    watched: dict
    valid: bool


class Mechanism(ABC):
    """One linkage of one mechanism, and everything shared code may ask of it.

    Class attributes: `name` (the `[linkage] mechanism` value), `NO_ASSEMBLY` (the note
    when it never assembles), `DEAD_POINT` (what a dead point of its loads means, for the
    forces note), `TOGGLE` (what an infinite mechanical advantage means, for the same note)."""

    name: ClassVar[str]
    NO_ASSEMBLY: ClassVar[str]
    DEAD_POINT: ClassVar[str]
    TOGGLE: ClassVar[str] = "input and coupler in line, the output stands still"

    def __init__(self, linkage) -> None:
        self.linkage = linkage

    # ------------------------------------------------------------ scale and report
    @abstractmethod
    def size(self) -> float:
        """The linkage's length scale: round-off below NOISE_FLOOR times it is 0."""

    @abstractmethod
    def lengths_section(self, units) -> dict:
        """The report's `linkage` section (a result file's `[linkage]` reads back)."""

    @abstractmethod
    def class_section(self, units) -> dict:
        """The report's `grashof` section: the class and the figures that decide it."""

    def linkage_notes(self, want: set, units) -> list[str]:
        """Warnings about the linkage itself (a change point ...), given the asked sections."""
        return []

    @abstractmethod
    def study(self, near: float | None = None) -> Study | None:
        """The drive's range for the motion study (the arc holding `near` when it rocks in
        several arcs); None when it never assembles."""

    @abstractmethod
    def transmission_section(self, study: Study, span, units, notes: list) -> dict:
        """The `transmission` section over the study's range (and the working `span`,
        (start, signed sweep) rad, where a problem has targets); notes get the band warning."""

    @abstractmethod
    def motion_section(self, study: Study, units) -> dict:
        """The `motion` section: range of motion of the drive and the output."""

    @abstractmethod
    def kinematics_rows(self, study: Study, speed: float, steps: int, units) -> list[dict]:
        """The `kinematics` rows at `study.rows(steps)` for a constant drive `speed` rad/s."""

    def study_keys(self, speed: float, steps: int, units) -> dict:
        """What the `motion` section records to reproduce the study: the [motion] input speed
        (angle unit per s) and steps (a home whose drives carry their own speeds: steps)."""
        return {"input_speed": float(units.from_rad(float(speed))), "steps": steps}

    # ------------------------------------------------------------ loads
    @abstractmethod
    def load_rows(self, phi, speed: float, case, metres: float) -> LoadRows:
        """Inverse dynamics at drive angles phi turning at `speed` rad/s (constant) under the
        load case (model.LoadCase); lengths times `metres` are metres."""

    def member_forces(self, phi, speed: float, case, metres: float,
                      rows: LoadRows) -> MemberForces | None:
        """The loads on every moving link and the force through every revolute pin at drive
        angles phi (the rows of `rows`, this home's `load_rows(phi, speed, case, metres)`),
        for the strength section (analysis.strength). Contract (MemberForces): forces ON
        each link in N at points in m, global frame; each link's loads in equilibrium with
        its own mass's weight and d'Alembert inertia included; NaN at the rows `rows`
        marks singular. Links are named as the home's schema `LINKS`, joints as `JOINTS`.
        None (this default): the home does not give them, and a file asking for the
        strength section is told so (exit 2)."""
        return None

    # ------------------------------------------------------------ dynamics
    def body_graph(self, case, metres: float) -> BodyGraph | None:
        """The linkage as bodies, pins and guides (BodyGraph) with the masses and constant
        loads of `case` (model.LoadCase; lengths times `metres` are metres). None (this
        default): the home gives no dynamics, and a file with [dynamics] is told so."""
        return None

    def coefficients(self, q, metres: float) -> Coefficients:
        """The kinematic coefficients (Coefficients) at drive values q, the drive's values as
        the home reports its rows (`Study.rows`; several drives: rows of (q_1 .. q_k), as its
        body_graph lists them), lengths in metres."""
        raise NotImplementedError(f"{self.name} gives no kinematic coefficients")

    def coefficients_at(self, q, metres: float) -> PointCoefficients:
        """The kinematic coefficients at one state q (k drive values) in Python floats, for a
        linkage of several drives (whose equation of motion is evaluated exactly at every step).
        This default takes `coefficients` at one row; a home may give a faster path."""
        coef = self.coefficients(np.asarray([q], dtype=float), metres)
        k = coef.drives
        if not bool(coef.valid[0]):
            return PointCoefficients({}, {}, 0.0, {name: 0.0 for name in coef.watched}, False)

        def pair(a):
            return (float(a[0]), float(a[1]))
        origin = {body: (pair(x[0]), tuple(pair(dx[0, :, j]) for j in range(k)),
                         tuple(tuple(pair(ddx[0, :, i, j]) for j in range(k)) for i in range(k)))
                  for body, (x, dx, ddx) in coef.origin.items()}
        angle = {body: (float(t[0]), tuple(float(dt[0, j]) for j in range(k)),
                        tuple(tuple(float(ddt[0, i, j]) for j in range(k)) for i in range(k)))
                 for body, (t, dt, ddt) in coef.angle.items()}
        return PointCoefficients(origin, angle, float(coef.lock[0]),
                                 {name: float(v[0]) for name, v in coef.watched.items()}, True)

    def input_origin(self) -> float:
        """The drive value a design's `positions` inputs count from (rad or length): 0 (this
        default: they are the drive's own values, as `skeleton` takes them); a home whose
        targets' inputs are offsets from its drawn position: that position's drive value."""
        return 0.0

    def study_speed(self, speed: float) -> float:
        """The drive's speed (rad/s) of the motion study whose [motion] input speed is `speed`
        (this default: that speed; a home whose drives carry their own speeds: its drive's)."""
        return speed

    def counterweights(self, graph: BodyGraph, metres: float) -> dict | None:
        """Counterweights that cancel the shaking force: body -> (mass x radius kg m, angle rad
        in the body's frame, the radius they take by default m), for the masses of `graph`
        (its body_graph(case, metres)); None (this default) when the home has no such rule."""
        return None

    # ------------------------------------------------------------ tolerance
    @abstractmethod
    def tolerance_model(self, problem, solution):
        """The made-part model of the tolerance Monte Carlo (analysis.tolerance.Model)."""

    # ------------------------------------------------------------ drawing
    @abstractmethod
    def skeleton(self, phi) -> Skeleton:
        """Joints, links, ground pivots and guides at drive angles phi, global frame."""

    @classmethod
    def joint_paths(cls, linkages, phi) -> dict[str, np.ndarray]:
        """The skeleton's joints of many linkages of this home at once: name -> (K, n, 2), the
        k-th linkage at its drive angles phi[k] (phi: (K, n); NaN where it does not assemble),
        the same numbers as each linkage's `skeleton(phi[k]).joints`. This default: linkage by
        linkage; a home overrides it with its closed forms vectorized over linkages x angles.
        ValueError: the linkages' skeletons name different joints."""
        phi = np.asarray(phi, dtype=float)
        each = [cls(linkage).skeleton(row).joints for linkage, row in zip(linkages, phi)]
        names = tuple(each[0]) if each else ()
        if any(tuple(joints) != names for joints in each):
            raise ValueError("the linkages' skeletons name different joints")
        return {name: np.stack([np.asarray(joints[name], dtype=float).reshape(phi.shape[1], 2)
                                for joints in each]) for name in names}

