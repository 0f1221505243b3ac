"""Frozen dataclasses: units, the four-bar, and one class per problem type (a tagged union).

Inside, lengths are in the file's length unit and angles in radians; `Units` converts
angles back for output. Problem classes hold validated data only: no numerics here.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

from linkcli.units import Units

LINKS = ("ground", "input", "coupler", "output")
BRANCHES = ("open", "crossed")


@dataclass(frozen=True)
class SliderCrank:
    """An offset slider-crank: lengths in the length unit; coupler_point (px, py) in the
    coupler frame (origin A, x along A -> B), as the four-bar's (the conventions of docs/format.md)."""

    mechanism: ClassVar[str] = "slider-crank"  # its home: linkcli.mechanisms
    input: float
    coupler: float
    offset: float
    branch: str = "open"
    coupler_point: tuple[float, float] | None = None

    @property
    def abe(self) -> tuple[float, float, float]:
        """(crank, rod, offset)."""
        return self.input, self.coupler, self.offset


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


@dataclass(frozen=True)
class FourBar:
    """A planar four-bar (the conventions of docs/format.md). Lengths in the length unit, angles in radians."""

    mechanism: ClassVar[str] = "four-bar"  # its home: linkcli.mechanisms
    ground: float
    input: float
    coupler: float
    output: float
    branch: str = "open"
    coupler_point: tuple[float, float] | None = None
    ground_pivot: tuple[float, float] = (0.0, 0.0)
    ground_angle: float = 0.0
    coupler_angle: float | None = None  # motion generation: the body's x axis from A -> B, rad

    @property
    def abcd(self) -> tuple[float, float, float, float]:
        """Seed-paper letters: a = input, b = coupler, c = output, d = ground."""
        return (self.input, self.coupler, self.output, self.ground)


@dataclass(frozen=True)
class PrecisionPositionProblem:
    """Freudenstein function generation through paired (phi_i, psi_i) positions."""

    meta: Meta
    ground: float | None  # None for a slider-crank (it has no ground link)
    input_angles: tuple[float, ...]
    output_angles: tuple[float, ...]  # slider-crank: slider positions s_i (length unit)
    lines: tuple[int | None, ...] = ()  # line of each position pair, for messages
    input_speed: float = 1.0  # rad/s, [motion] of the kinematics section
    steps: int = 360
    mechanism: str = "four-bar"  # or "slider-crank" ([linkage] mechanism)


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
    lengths_given: bool = False  # `lengths` written in the file (0 included): the study uses it


@dataclass(frozen=True)
class PathGenerationProblem:
    """A coupler point through target points (docs/format.md, path-generation).

    Every bound is (lo, hi); lo == hi fixes the value. Lengths in the length unit (a
    length's lo may be 0: the solver keeps it strictly positive), angles in radians.
    `input_angles` (prescribed timing) are measured in the local frame from A0 -> B0."""

    mechanism: ClassVar[str] = "four-bar"  # the mechanism designed (types.path_generation.schema.DESIGNS)
    meta: Meta
    points: tuple[tuple[float, float], ...]  # targets, global frame
    timing: str  # "prescribed" or "free"
    input_angles: tuple[float, ...] | None  # prescribed timing: one per point, rad
    direction: str  # free timing: "ccw", "cw" or "either" (the solver picks)
    lengths: dict  # "ground", "input", "coupler", "output" -> (lo, hi)
    coupler_point: tuple[tuple[float, float], tuple[float, float]]  # (x lo, hi), (y lo, hi)
    ground_pivot: tuple[tuple[float, float], tuple[float, float]]
    ground_angle: tuple[float, float]  # rad
    input_offset: tuple[float, float] | None = None  # prescribed timing: rad, added to every angle
    grashof: str = "any"  # a class of mechanisms.four_bar.kinematics.GRASHOF_CLASSES (not change-point) or "any"
    transmission: tuple[float, float] | None = None  # window on mu, rad
    branch: str = "either"  # "open", "crossed" or "either"
    lines: dict = field(default_factory=dict)  # key -> line of the file, for messages
    objective: str = "error"  # [objective] minimize: "error" or "failure-probability" (robust design)
    defect_free: float = 0.99  # [constraints] defect_free: least share of made linkages that assemble


@dataclass(frozen=True)
class MotionGenerationProblem:
    """A body guided through poses (docs/format.md, motion-generation). Poses (x, y, angle)
    in the length unit and radians, global frame; pivots as given ((x, y) pairs: A0 and B0
    global, or A and B in the body frame), bounds like PathGenerationProblem."""

    meta: Meta
    poses: tuple[tuple[float, float, float], ...]
    timing: str  # "free" or "prescribed"
    input_angles: tuple[float, ...] | None  # prescribed timing: one per pose, rad
    angle_weight: float | None  # length; None: the poses' characteristic length
    ground_pivots: tuple[tuple[float, float], tuple[float, float]] | None
    moving_pivots: tuple[tuple[float, float], tuple[float, float]] | None
    lengths: dict  # "ground", "input", "coupler", "output" -> (lo, hi)
    ground_pivot: tuple[tuple[float, float], tuple[float, float]]
    ground_angle: tuple[float, float]  # rad
    input_offset: tuple[float, float] | None = None  # prescribed timing: rad
    grashof: str = "any"
    transmission: tuple[float, float] | None = None  # window on mu, rad
    branch: str = "either"
    lines: dict = field(default_factory=dict)  # key -> line of the file, for messages


@dataclass(frozen=True)
class FunctionGenerationProblem:
    """Function generation by optimization: free lengths (and start angles) such that the
    output angle psi follows a law over the input sweep (docs/format.md).

    Two forms: `form = "output"`, psi = law(phi, phi0, psi0) with phi from phi0 to
    phi0 + input_sweep; `form = "function"`, y = f(x) mapped linearly onto the input and
    output sweeps (`shape` holds (f(x_k) - f(x0)) / (f(x1) - f(x0)) at each point).
    The evaluation points sit at phi_k = phi0 + fractions[k] * input_sweep.
    """

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


@dataclass(frozen=True)
class QuickReturnProblem:
    """A crank-rocker or slider-crank designed by its time ratio (SPEC section 2,
    quick-return). Lengths in the length unit, angles in radians."""

    meta: Meta
    mechanism: str  # "crank-rocker" or "slider-crank"
    time_ratio: float  # K >= 1
    swing: float | None = None  # crank-rocker: rocker swing, rad, in (0, pi)
    stroke: float | None = None  # slider-crank: slider stroke
    scale: tuple[str, float] | None = None  # crank-rocker: ("ground" | "output", length)
    offset: float | None = None  # slider-crank: given (signed) offset; None: free
    bounds: dict = field(default_factory=dict)  # "parameter" | a length -> (lo, hi)
    transmission: tuple[float, float] | None = None  # window on mu over the full turn, rad
    lines: dict = field(default_factory=dict)  # key ("swing", "linkage.offset", ...) -> line
