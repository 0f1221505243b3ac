"""Path generation as a vector of variables and a vector of residuals (numpy only).

Variables of one candidate (the full vector; a fixed one has lo == hi):

    0 ground d, 1 input a, 2 coupler b, 3 output c, 4 px, 5 py (coupler point, coupler
    frame), 6 gx, 7 gy (ground pivot A0), 8 gamma (ground angle), then the timing:
    prescribed: 9 offset (added to every input angle); free: 9 phi_1, 10.. the increments
    delta_k >= 0 from one target's input angle to the next (k = 2..n).

Free timing: phi_k = phi_1 + s (delta_2 + ... + delta_k), s = +1 (the input turns
counter-clockwise) or -1; the order of the targets is then held by the bounds delta_k >= 0,
and "within one turn" is the inequality sum(delta) <= 2 pi. Each candidate also carries a
branch sign (-1 open, +1 crossed, the conventions of docs/format.md), held at every target.

Coupler point in the global frame (the conventions of docs/format.md): with A = a e^{i phi}, theta the coupler
angle from the closure on the branch,

    P = G + R(gamma) (A + R(theta) p),    objective = sum_k |P_k - T_k|^2.

Residuals are scaled by the targets' extent L (dimensionless); the constraints add
penalty residuals w * max(0, g) with g <= 0 the feasible side (`Design.penalties`).
Everything is vectorized over candidates (rows) and targets (columns).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from linkcli.io.bounds import MIN_LENGTH as FILE_MIN_LENGTH
from linkcli.mechanisms.four_bar import closure
from linkcli.mechanisms.four_bar import kinematics as kin

NAMES = ("ground", "input", "coupler", "output", "coupler_point_x", "coupler_point_y",
         "ground_pivot_x", "ground_pivot_y", "ground_angle")
N_LINK = len(NAMES)
FULL_TURN = ("crank-rocker", "double-crank")  # classes whose input must turn fully
MIN_LENGTH = 1e-6  # relative to the length's upper bound: a lower bound of 0 becomes this
ABSOLUTE_MIN_LENGTH = FILE_MIN_LENGTH  # and at least the shortest length a file may hold
HUGE = 1e100  # a residual that overflowed
GRASHOF_MARGIN = 1e-7  # relative: s + l <= p + q - margin (s + l + p + q), clear of the change point
# The link that must be shortest for each Grashof class (index into d, a, b, c).
SHORTEST = {"crank-rocker": 1, "double-crank": 0, "rocker-crank": 3, "double-rocker": 2}


@dataclass
class Design:
    """A problem as bounds on the full variable vector plus what the residuals need."""

    targets: np.ndarray  # (n, 2)
    timing: str  # "prescribed" or "free"
    base_phi: np.ndarray | None  # (n,) prescribed input angles, rad
    lo: np.ndarray  # (nx,) full-vector bounds
    hi: np.ndarray
    grashof: str
    window: tuple[float, float] | None  # transmission window, rad
    branch: str  # "open", "crossed", "either"
    direction: str  # free timing: "ccw", "cw", "either"
    scale: float  # L: the targets' extent, for dimensionless residuals
    # Angles free over a full turn (ground angle, prescribed offset): index -> start of the
    # user's range. Their search bounds reach one more turn on each side (`build`), so that a
    # local search can cross the seam of the range; `wrapped` brings them back into it.
    periodic: dict = field(default_factory=dict)

    @property
    def n_targets(self) -> int:
        return len(self.targets)

    @property
    def nx(self) -> int:
        return len(self.lo)

    @property
    def free(self) -> np.ndarray:
        return self.hi > self.lo

    @property
    def full_turn(self) -> bool:
        return self.grashof in FULL_TURN

    @property
    def n_penalties(self) -> int:
        grashof = 3 if self.grashof in SHORTEST else (1 if self.grashof == "triple-rocker" else 0)
        window = 2 if self.window is not None else 0
        turn = 1 if self.timing == "free" else 0
        return grashof + window + self.n_targets + 2 + turn

    def wrapped(self, x: np.ndarray) -> np.ndarray:
        """x (N, nx) with every periodic angle brought into [lo, lo + 2 pi) of its user range
        (the same linkage: these angles enter only through their cosine and sine)."""
        if not self.periodic:
            return x
        x = x.copy()
        for j, lo in self.periodic.items():
            x[:, j] = lo + np.mod(x[:, j] - lo, kin.TWO_PI)
        return x

    # ---------------------------------------------------------------- timing
    def input_angles(self, x: np.ndarray, s: np.ndarray) -> np.ndarray:
        """(N, n) input angles of candidates x (N, nx) turning in direction s (N,)."""
        if self.timing == "prescribed":
            return self.base_phi[None, :] + x[:, N_LINK:N_LINK + 1]
        steps = np.concatenate([np.zeros((len(x), 1)), np.cumsum(x[:, N_LINK + 1:], axis=1)], axis=1)
        return x[:, N_LINK:N_LINK + 1] + s[:, None] * steps

    def span(self, phi: np.ndarray):
        """(lo, width) of the input's travel over the targets, each (N,): the hull of the
        angles in the order they are visited (monotone for free timing)."""
        lo = phi.min(axis=1)
        return lo, phi.max(axis=1) - lo

    # ---------------------------------------------------------------- residuals
    def frame(self, x: np.ndarray, sign: np.ndarray, s: np.ndarray):
        """The closure (`closure.Frame`) of candidates x (N, nx) at their input angles, and
        those angles (N, n)."""
        d, a, b, c = (x[:, k:k + 1] for k in range(4))
        phi = self.input_angles(x, s)
        return closure.frame(a, b, c, d, phi, sign[:, None]), phi

    def points(self, x: np.ndarray, sign: np.ndarray, s: np.ndarray, pose: closure.Frame | None = None):
        """Global coupler points (N, n, 2), the pose and the input angles (`pose`: the
        closure at these lengths and angles when the caller has it already)."""
        if pose is None:
            p, phi = self.frame(x, sign, s)
        else:
            p, phi = pose, self.input_angles(x, s)
        lx, ly = p.coupler_point(x[:, 1:2], x[:, 4:5], x[:, 5:6])
        cg, sg = np.cos(x[:, 8:9]), np.sin(x[:, 8:9])
        gx = x[:, 6:7] + cg * lx - sg * ly
        gy = x[:, 7:8] + sg * lx + cg * ly
        return np.stack([gx, gy], axis=-1), p, phi

    def residuals(self, x: np.ndarray, sign: np.ndarray, s: np.ndarray, weight: float,
                  pose: closure.Frame | None = None) -> np.ndarray:
        """(N, 2n + m): target errors / L, then weight * constraint violations."""
        pts, p, phi = self.points(x, sign, s, pose)
        err = (pts - self.targets[None]).reshape(len(x), -1) / self.scale
        if weight != 0.0:
            err = np.concatenate([err, weight * self.penalties(x, p, phi)], axis=1)
        # absurd inputs (lengths of 1e-300 beside 1e300) overflow: keep them finite and large
        return np.nan_to_num(err, nan=HUGE, posinf=HUGE, neginf=-HUGE)

    def penalty_residuals(self, x: np.ndarray, s: np.ndarray, weight: float) -> np.ndarray:
        """(N, m) the penalty part of `residuals` alone (weight * violations): the
        constraints need only rho = |A B0| of the closure, computed as `closure.frame` does
        (the same bits), not the coupler points."""
        phi = self.input_angles(x, s)
        a, d = x[:, 1:2], x[:, 0:1]
        rho = np.hypot(a * np.cos(phi) - d, a * np.sin(phi))
        out = weight * self.penalties(x, RhoOnly(rho), phi)
        return np.nan_to_num(out, nan=HUGE, posinf=HUGE, neginf=-HUGE)

    def objective(self, x, sign, s) -> np.ndarray:
        """(N,) sum of squared distances (length unit^2)."""
        pts, _, _ = self.points(x, sign, s)
        return np.sum((pts - self.targets[None]) ** 2, axis=(1, 2))

    def penalties(self, x: np.ndarray, p: closure.Frame, phi: np.ndarray) -> np.ndarray:
        """(N, m) constraint violations max(0, g) / L, g <= 0 feasible (see `constraints`)."""
        return np.maximum(0.0, self.constraints(x, p, phi)) / self.scale

    def constraints(self, x: np.ndarray, p: closure.Frame, phi: np.ndarray) -> np.ndarray:
        """(N, m) constraint functions g (length unit; g <= 0 is feasible):

        Grashof class with shortest link s:  s + x_j - (sum of the other two) + margin <= 0
            for each other link x_j (together: s is shortest and s + l < p + q);
        triple-rocker: p + q - s - l + margin <= 0;
        transmission window [mu_lo, mu_hi]: mu rises with rho = |A B0|, so
            L (cos mu(rho_min) - cos mu_lo) <= 0 and L (cos mu_hi - cos mu(rho_max)) <= 0,
            rho over the full turn (|d - a|, d + a) or over the span of the targets;
        assembly at each target: |b - c| <= rho_k <= b + c;
        no dead point inside the span: the same at phi = 0 and pi when the span holds them;
        free timing, within one turn: L (sum delta - 2 pi) <= 0.
        """
        d, a, b, c = (x[:, k] for k in range(4))
        cols = []
        links = np.stack([d, a, b, c], axis=1)
        total = links.sum(axis=1)
        margin = GRASHOF_MARGIN * total
        if self.grashof in SHORTEST:
            k = SHORTEST[self.grashof]
            others = [j for j in range(4) if j != k]
            for j in others:
                rest = [o for o in others if o != j]
                cols.append(links[:, k] + links[:, j] - links[:, rest[0]] - links[:, rest[1]] + margin)
        elif self.grashof == "triple-rocker":
            srt = np.sort(links, axis=1)
            cols.append(srt[:, 1] + srt[:, 2] - srt[:, 0] - srt[:, 3] + margin)
        lo_span, width = self.span(phi)
        if self.window is not None:
            if self.full_turn:
                r2_min, r2_max = (d - a) ** 2, (d + a) ** 2
            else:
                r2_min, r2_max = rho2_extremes(a, d, lo_span, width)
            cos_mu = lambda r2: (b * b + c * c - r2) / (2.0 * b * c)
            cols.append(self.scale * (cos_mu(r2_min) - math.cos(self.window[0])))
            cols.append(self.scale * (math.cos(self.window[1]) - cos_mu(r2_max)))
        bc_lo, bc_hi = np.abs(b - c)[:, None], (b + c)[:, None]
        out = np.concatenate([np.stack(cols, axis=1) if cols else np.zeros((len(x), 0)),
                              np.maximum(bc_lo - p.rho, p.rho - bc_hi)], axis=1)
        dead = []
        for at, rho in ((0.0, np.abs(a - d)), (math.pi, a + d)):
            inside = np.mod(at - lo_span, kin.TWO_PI) <= width
            v = np.maximum(np.abs(b - c) - rho, rho - (b + c))
            dead.append(np.where(inside, v, np.minimum(v, 0.0)))
        out = np.concatenate([out, np.stack(dead, axis=1)], axis=1)
        if self.timing == "free":
            sweep = x[:, N_LINK + 1:].sum(axis=1)
            out = np.concatenate([out, (self.scale * (sweep - kin.TWO_PI))[:, None]], axis=1)
        return out


@dataclass
class RhoOnly:
    """What `Design.constraints` reads of a pose: rho = |A B0| at each target."""

    rho: np.ndarray


def rho2_extremes(a, d, lo, width):
    """min and max of rho^2 = a^2 + d^2 - 2 a d cos(phi) for phi in [lo, lo + width]:
    at the ends, or at phi = 0 (min) / pi (max) when the interval holds them."""
    ends = np.stack([lo, lo + width], axis=1)
    r2 = a[:, None] ** 2 + d[:, None] ** 2 - 2 * a[:, None] * d[:, None] * np.cos(ends)
    has0 = np.mod(-lo, kin.TWO_PI) <= width
    has_pi = np.mod(math.pi - lo, kin.TWO_PI) <= width
    r2_min = np.where(has0, (a - d) ** 2, r2.min(axis=1))
    r2_max = np.where(has_pi, (a + d) ** 2, r2.max(axis=1))
    return r2_min, r2_max


def build(problem) -> Design:
    """The Design of a validated PathGenerationProblem."""
    targets = np.array(problem.points, dtype=float)
    ext = targets.max(axis=0) - targets.min(axis=0)
    scale = float(max(ext.max(), 1e-300))
    lengths = [problem.lengths[k] for k in ("ground", "input", "coupler", "output")]
    # a lower bound of 0 becomes MIN_LENGTH x its upper bound, and never less than the
    # smallest length a file may hold (io.bounds.MIN_LENGTH, absolute): targets 1e-9 apart
    # must not give a ground of 5e-10 that no file could state
    lo = [max(l, MIN_LENGTH * h, ABSOLUTE_MIN_LENGTH) if l < h else l for l, h in lengths]
    hi = [h for _, h in lengths]
    (cxl, cxh), (cyl, cyh) = problem.coupler_point
    (gxl, gxh), (gyl, gyh) = problem.ground_pivot
    gal, gah = problem.ground_angle
    lo += [cxl, cyl, gxl, gyl, gal]
    hi += [cxh, cyh, gxh, gyh, gah]
    n = len(targets)
    if problem.timing == "prescribed":
        off = problem.input_offset or (0.0, 0.0)
        lo.append(off[0])
        hi.append(off[1])
        base = np.array(problem.input_angles, dtype=float)
    else:
        lo += [-3 * math.pi] + [0.0] * (n - 1)
        hi += [3 * math.pi] + [kin.TWO_PI] * (n - 1)
        base = None
    periodic = {}
    for j in (8, N_LINK) if problem.timing == "prescribed" else (8,):
        if hi[j] - lo[j] >= kin.TWO_PI * (1 - 1e-12):  # a full turn: no seam for the search
            periodic[j] = lo[j]
            lo[j], hi[j] = lo[j] - kin.TWO_PI, hi[j] + kin.TWO_PI
    return Design(targets=targets, timing=problem.timing, base_phi=base, lo=np.array(lo, float),
                  hi=np.array(hi, float), grashof=problem.grashof, window=problem.transmission,
                  branch=problem.branch, direction=problem.direction, scale=scale, periodic=periodic)
