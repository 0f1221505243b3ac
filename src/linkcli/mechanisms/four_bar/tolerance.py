"""The four-bar's made parts for the tolerance Monte Carlo (analysis.tolerance drives it).

Lengths. Every link length l (ground included) is made as l + dl; for a path generator the
coupler point (px, py) can carry a tolerance too (each coordinate +- t, table key
`coupler_point`).

Joint clearance, effective-link model. At each revolute joint (A0, A, B, B0) the journal
centre lies anywhere in a circle of radius r (the radial clearance) around the bearing
centre: each clearance is a massless virtual link of length <= r whose direction is set by
the load (Lee & Gilmore 1991, "The determination of the probabilistic properties of
velocities and accelerations in kinematic chains with uncertainty", J. Mech. Des. 113;
Ting, Zhu & Watkins 2000, "The effects of joint clearance on position and orientation
deviation of linkages and manipulators", Mech. Mach. Theory 35). With the offsets e1..e4
(at A0, A, B, B0) the loop closes as

    e1 + a e^{i phi} + e2 + b e^{i theta} + e3 = d + e4 + c e^{i psi},

a four-bar whose ground is the vector D = d + e4 - e1 - e2 - e3: `kinematics.pose` assembles
it with ground |D| at input phi - arg D, and the angles are turned back by arg D. The
coupler point is P = e1 + e2 + a e^{i phi} + (px + i py) e^{i theta}.

Error of one sample: the largest deviation over the targets, each sample assembled on the
design's branch at the target input angles: |psi - psi_target| (wrapped) for angle
targets, |P - P_target| for path targets. A problem without targets (`type = "linkage"`)
is measured against its own nominal output angle at 36 inputs spread over the input's
range of motion (every 10 deg for a full turn; the centres of 36 equal cells of a rocking
input's arc). A sample fails when a length comes out <= 0, when it cannot assemble at a
target, when its input cannot travel from the first to the last target without a dead
point (checked on the made lengths: rho^2 = a^2 + d^2 - 2 a d cos(phi) must stay within
[(b - c)^2, (b + c)^2], extreme only at the span's ends and at phi = 0, 180 deg), or when
its error exceeds `allowed_error`. Sensitivity: per link, max_j |d(output_j) / d(length)|
by a central difference on the nominal linkage.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.mechanisms.four_bar.model import LINKS, FourBar

COLUMNS = LINKS + ("coupler_point_x", "coupler_point_y")  # the toleranced dimensions, draw order
GRID = 36  # inputs over the range of motion for a problem without targets
TRAVEL_SLACK = 1e-12  # relative slack on rho^2 at the span's limits (as kinematics)
NO_ALLOWED_ERROR = ("no allowed_error given: a sample fails only when it cannot be made (a length "
                    "<= 0), assembled at a target or moved from the first target to the last")


@dataclass
class Targets:
    """What a manufactured linkage must reproduce, at input angles `phi` (rad)."""

    phi: np.ndarray  # (M,)
    kind: str  # "angle" (value: psi, rad) or "point" (value: (M, 2) global points)
    value: np.ndarray
    measure: str  # a sentence for the report
    span: tuple[float, float] | None  # (start, signed sweep) the input travels, rad


# ---------------------------------------------------------------- targets

def targets(problem, solution) -> Targets:
    """The solution's positions, or the nominal output over the range of motion."""
    fb = solution.linkage
    pos = solution.positions
    if pos is not None and len(pos.input):
        phi = np.asarray(pos.input, dtype=float)
        if pos.kind == "point":
            return Targets(phi, "point", np.asarray(pos.target, dtype=float).reshape(-1, 2),
                           "largest distance between coupler point and target point",
                           solution.working_span)
        return Targets(phi, "angle", np.asarray(pos.target, dtype=float),
                       "largest output-angle error at the target positions", solution.working_span)
    arcs = kin.input_arcs(*fb.abcd)
    if arcs is None:
        phi = np.arange(GRID) * (kin.TWO_PI / GRID)
        span = (0.0, kin.TWO_PI)
    elif arcs == []:
        phi = np.zeros(0)
        span = None
    else:
        near = solution.working_span[0] if solution.working_span else None
        lo, hi = kin.choose_arc(arcs, near)
        phi = lo + (np.arange(GRID) + 0.5) * ((hi - lo) / GRID)
        span = (float(phi[0]), float(phi[-1] - phi[0]))
    psi = kin.pose(*fb.abcd, phi, fb.branch).psi
    return Targets(phi, "angle", psi,
                   f"largest deviation from the nominal output angle at {len(phi)} inputs "
                   "over the input's range of motion", span)


# ---------------------------------------------------------------- one batch of samples

def offsets(off: np.ndarray | None):
    """The clearance offsets (n, M, 4, 2) as complex e1..e4 (A0, A, B, B0), or None."""
    if off is None:
        return None
    return tuple(off[:, :, j, 0] + 1j * off[:, :, j, 1] for j in range(4))


def sample_outputs(fb: FourBar, tg: Targets, dl: np.ndarray, off):
    """Outputs of manufactured linkages at the targets.

    dl (n, 6): deviations of ground, input, coupler, output, px, py; off (n, M, 4, 2):
    clearance offsets at A0, A, B, B0 (or `offsets` of them), or None. Returns (out, ok): out
    (n, M) output angles (rad) or (n, M, 2) global coupler points; ok (n, M) where the sample
    assembles.
    """
    if isinstance(off, np.ndarray):
        off = offsets(off)
    d = fb.ground + dl[:, 0:1]
    a = fb.input + dl[:, 1:2]
    b = fb.coupler + dl[:, 2:3]
    c = fb.output + dl[:, 3:4]
    made = (a > 0) & (b > 0) & (c > 0) & (d > 0)
    a, b, c, d = (np.where(made, x, 1.0) for x in (a, b, c, d))
    phi = tg.phi[None, :]
    if off is None:
        gamma = 0.0
        p = kin.pose(a, b, c, d, phi, fb.branch)
        psi, theta = p.psi, p.theta
    else:
        e1, e2, e3, e4 = off
        big_d = d + e4 - e1 - e2 - e3
        gamma = np.angle(big_d)
        p = kin.pose(a, b, c, np.abs(big_d), phi - gamma, fb.branch)
        psi, theta = p.psi + gamma, p.theta + gamma
    ok = p.valid & made
    if tg.kind == "angle":
        return psi, ok
    px, py = fb.coupler_point or (0.0, 0.0)
    cp = (px + dl[:, 4:5]) + 1j * (py + dl[:, 5:6])
    local = a * np.exp(1j * phi) + cp * np.exp(1j * theta)
    if off is not None:
        local = local + off[0] + off[1]  # the coupler's bore at A moves with both pins
    glob = complex(*fb.ground_pivot) + np.exp(1j * fb.ground_angle) * local
    return np.stack([glob.real, glob.imag], axis=-1), ok


def travel_ok(fb: FourBar, dl: np.ndarray, span) -> np.ndarray:
    """(n,) whether each sample's input can run over `span` without a dead point."""
    if span is None:
        return np.ones(len(dl), dtype=bool)
    start, sweep = span
    lo, width = (start, sweep) if sweep >= 0 else (start + sweep, -sweep)
    cands = [lo, lo + width] + [x for x in (0.0, math.pi)
                                if np.mod(x - lo, kin.TWO_PI) <= width + 1e-12]
    x = np.array(cands)[None, :]
    d = fb.ground + dl[:, 0:1]
    a = fb.input + dl[:, 1:2]
    b = fb.coupler + dl[:, 2:3]
    c = fb.output + dl[:, 3:4]
    rho2 = a * a + d * d - 2.0 * a * d * np.cos(x)
    lo2, hi2 = (b - c) ** 2, (b + c) ** 2
    slack = TRAVEL_SLACK * hi2
    return np.all((rho2 >= lo2 - slack) & (rho2 <= hi2 + slack), axis=1)


def target_deviations(fb: FourBar, tg: Targets, dl: np.ndarray, off) -> np.ndarray:
    """(n, M) each made linkage's deviation at each target (rad or length): inf at a target
    where it cannot assemble, and at every target when it cannot be made or travel."""
    out, ok = sample_outputs(fb, tg, dl, off)
    if tg.kind == "angle":
        dev = np.abs(kin.wrap(out - tg.value[None, :]))
    else:
        dev = np.hypot(out[..., 0] - tg.value[None, :, 0], out[..., 1] - tg.value[None, :, 1])
    return np.where(ok & travel_ok(fb, dl, tg.span)[:, None], dev, np.inf)


def sample_errors(fb: FourBar, tg: Targets, dl: np.ndarray, off: np.ndarray | None):
    """(err, ok), each (n,): largest deviation over the targets (rad or length; inf where
    the sample fails to assemble or to travel) and whether it assembles and travels."""
    out, ok = sample_outputs(fb, tg, dl, off)
    if tg.kind == "angle":
        dev = np.abs(kin.wrap(out - tg.value[None, :]))
    else:
        dev = np.hypot(out[..., 0] - tg.value[None, :, 0], out[..., 1] - tg.value[None, :, 1])
    ok_all = np.all(ok, axis=1) & travel_ok(fb, dl, tg.span)
    err = np.where(ok_all, dev.max(axis=1), np.inf)
    return err, ok_all



def sensitivity(fb: FourBar, tg: Targets) -> dict:
    """Per link, max over targets of |d output / d length| (rad or length per length),
    by a central difference on the nominal linkage (one vectorized assembly)."""
    h = 1e-6 * max(fb.abcd)
    dl = np.zeros((2 * len(LINKS), len(COLUMNS)))
    for k in range(len(LINKS)):
        dl[2 * k, k], dl[2 * k + 1, k] = h, -h
    out, ok = sample_outputs(fb, tg, dl, None)
    if tg.kind == "angle":
        diff = kin.wrap(out[0::2] - out[1::2]) / (2 * h)
        mag = np.abs(diff)
    else:
        diff = (out[0::2] - out[1::2]) / (2 * h)
        mag = np.hypot(diff[..., 0], diff[..., 1])
    good = ok[0::2] & ok[1::2]
    res = {}
    for k, link in enumerate(LINKS):
        res[link] = float(mag[k].max()) if good[k].all() and mag.shape[1] else None
    return res




class Model:
    """The four-bar's made parts (analysis.tolerance.Model) for a solved problem."""

    columns = COLUMNS
    inverse = LINKS
    pins = 4  # A0, A, B, B0
    plays = 0
    per_row = False  # the report gives the largest error over the targets only
    pin_names = ("A0", "A", "B", "B0")  # as [joints] names them, in the order of the offsets
    play_names = ()
    keys = {"coupler_point_x": "coupler_point", "coupler_point_y": "coupler_point"}  # [tolerance] lengths keys
    no_assembly = "the nominal linkage cannot assemble at any input angle"
    no_allowed_error = NO_ALLOWED_ERROR

    def __init__(self, fb: FourBar, tg: Targets) -> None:
        self.fb, self.tg = fb, tg
        self.kind = "angle" if tg.kind == "angle" else "length"
        self.measure = tg.measure
        self.inputs = tg.phi
        self.scale = 1.0 if tg.kind == "angle" else max(fb.abcd)
        self.cap = min(fb.abcd)
        self.known = {k: getattr(fb, k) for k in LINKS}
        px, py = fb.coupler_point or (0.0, 0.0)
        self.nominal = {**self.known, "coupler_point_x": px, "coupler_point_y": py}  # sizes (ISO 2768)

    def given(self, tol) -> dict:
        return {}

    def play_size(self, tol) -> float:
        return 0.0

    def errors(self, dl, pins, plays):
        return sample_errors(self.fb, self.tg, dl, pins)

    def clearance_terms(self, pins, plays):
        """What the pins add, whatever the lengths: the offsets as complex numbers."""
        return offsets(pins)

    def errors_from_terms(self, dl, terms):
        return sample_errors(self.fb, self.tg, dl, terms)

    def deviations(self, dl, terms):
        """(n, M) deviation at each target (inf where it fails there): robust design."""
        return target_deviations(self.fb, self.tg, dl, terms)

    def sensitivity(self) -> dict:
        return sensitivity(self.fb, self.tg)
