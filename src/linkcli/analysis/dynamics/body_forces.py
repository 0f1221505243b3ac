"""The Newton-Euler equations of every body of a linkage in motion, with its force elements and
pin friction: the pin forces, the guides' normal forces, and the drive's acceleration (forward)
or torque (inverse), over rows at once (one (n, m, m) batched solve). SI.

Each moving link: sum F = m a_G, sum (P - G) x F + sum T = I_G alpha; each slider block (a
point mass at its joint): sum F = m a_J. With the kinematic coefficients, a_G = G' q'' + G'' q'^2
and alpha = theta' q'' + theta'' q'^2, so the equations are linear in the unknowns: the force of
each pin on the body it acts on (two components, as the home's BodyGraph names them; the body
exerting it feels the opposite), each guide's normal force N (along perp(u), on the block; the
guide's body feels the opposite), and q'' (forward, the drive's torque known) or the drive's
torque (inverse, q'' known). Norton, Design of Machinery, ch. 11; Paul, Kinematics and Dynamics
of Planar Machinery, ch. 13-14 (the same equations with the acceleration unknown).

Coulomb friction (the friction circle: Norton ch. 11; Shigley & Uicker ch. 13): in a pin of
diameter d joining bodies i and j, a couple of magnitude mu (d / 2) |F| opposing their relative
rotation (theta_j' - theta_i') q'; on a guide, a force mu |N| along the guide opposing the
block's sliding speed. Its sign is smoothed at rest, sign(x) ~ x / sqrt(x^2 + eps^2) with eps
the file's friction_speed (pins: rad/s; guides: that times the linkage's size, m/s), so the
equation stays smooth and an integrator does not chatter. The couples depend on the pin forces,
which depend on the couples: solved by fixed-point iteration (each pass one linear solve of all
rows), until the forces change by less than FRICTION_RTOL of their scale, or by less than
FRICTION_STALL of it and no less than the pass before (the round-off of a larger system, as the
five-bar's twelve equations, stalls above FRICTION_RTOL); a row that does not
converge in FRICTION_ITERATIONS passes (friction locks the linkage) is NaN.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from linkcli.analysis.dynamics import bodies

FRICTION_RTOL = 1e-15  # to round-off: the couples are then a smooth function of the state
FRICTION_STALL = 1e-12  # or a change this small that no longer shrinks: round-off of a larger system
FRICTION_ITERATIONS = 200
SINGULAR_RCOND = 1e-13  # a row whose system is this near singular (a dead point) is NaN


@dataclass
class Loads:
    """Known loads at n rows: `point_forces` (body, point (n, 2), force (n, 2)) and `couples`
    (body, (n,)) on moving bodies (the ground's are dropped), and the drive's torque (n,) or
    None."""

    point_forces: list
    couples: list


@dataclass
class Friction:
    """mu; pin radii by report name (m); eps (rad/s) and eps_v (m/s): the smoothed sign."""

    mu: float
    radii: dict
    eps: float
    eps_v: float


@dataclass
class BodyForces:
    """What the solve gives: pins (name -> (n, 2) N, on the body acted on), guides (name -> (n,
    2) the normal force on the block, N), `drive` (n,): q'' (forward) or the torque (inverse),
    friction couples per pin and friction forces per guide (n,) (signed: on the body acted on,
    along +u on the block), converged (n,) bool."""

    pins: dict
    guides: dict
    drive: np.ndarray
    pin_friction: dict
    guide_friction: dict
    converged: np.ndarray


def smooth_sign(x, eps: float):
    return x / np.sqrt(x * x + eps * eps)


class Layout:
    """Rows and columns of the system of a BodyGraph (built once per graph)."""

    def __init__(self, graph) -> None:
        self.graph = graph
        self.row = {}
        m = 0
        for body in graph.bodies:
            self.row[body] = m
            m += 2 if body in graph.blocks else 3
        self.size = m
        self.pin_col = {}
        col = 0
        for name, *_ in graph.pins:
            self.pin_col[name] = col
            col += 2
        self.guide_col = {}
        for name, *_ in graph.guides:
            self.guide_col[name] = col
            col += 1
        self.drive_col = col
        self.drive_cols = tuple(range(col, col + len(graph.driven)))  # one per drive value
        if col + len(self.drive_cols) != m:
            raise ValueError(f"the body graph is not square: {m} equations, {col + len(self.drive_cols)} unknowns")


class Assembly:
    """The equations of a body graph at rows of its coefficients: the matrix (forward: the
    drive's acceleration unknown; inverse: its torque), and the right-hand sides of the known
    loads (module docstring)."""

    def __init__(self, graph, coef, forward: bool, held=()) -> None:
        self.graph, self.coef, self.forward = graph, coef, forward
        self.held = tuple(held)  # forward: drives held still (acceleration 0, their torque unknown)
        layout = self.layout = Layout(graph)
        n, m = len(coef.q), layout.size
        self.n = n
        self.k = coef.drives
        matrix = self.matrix = np.zeros((n, m, m))
        self.centres, self.rates = {}, {}
        for body in graph.bodies:
            r = layout.row[body]
            mass = graph.masses.get(body)
            mm = 0.0 if mass is None else mass.mass
            inertia = 0.0 if mass is None or body in graph.blocks else mass.inertia
            c, dc, ddc = bodies.centre(graph, coef, body)
            _, dth, ddth = coef.angle[body]
            if self.k == 1:  # one drive: its rates with the drive axes of k drives (k = 1)
                dc, ddc, dth, ddth = dc[..., None], ddc[..., None, None], dth[:, None], ddth[:, None, None]
            self.centres[body] = c
            self.rates[body] = (mm, inertia, dc, ddc, dth, ddth)
            if forward:
                for j, col in enumerate(layout.drive_cols):
                    if j in self.held:
                        continue
                    matrix[:, r:r + 2, col] = -mm * dc[..., j]
                    if body not in graph.blocks:
                        matrix[:, r + 2, col] = -inertia * dth[:, j]
        for j, ((_, driven), col) in enumerate(zip(graph.driven, layout.drive_cols)):
            if not forward or j in self.held:
                matrix[:, layout.row[driven] + 2, col] = 1.0
        self.joint_at = {}
        for name, joint, exerting, acted in graph.pins:
            at = bodies.point(graph, coef, joint)[0]
            self.joint_at[joint] = at
            col = layout.pin_col[name]
            _unknown_force(matrix, layout, self.centres, acted, at, col, 1.0)
            _unknown_force(matrix, layout, self.centres, exerting, at, col, -1.0)
        self.guide_dir = {}
        for name, joint, guide, block, local in graph.guides:
            at = bodies.point(graph, coef, joint)
            u = bodies.rotated(np.asarray(local, dtype=float), bodies.angle(coef, guide)[0])
            normal = bodies.perp(u)
            self.guide_dir[name] = (u, normal, at, guide, block)
            col = layout.guide_col[name]
            _unknown_along(matrix, layout, self.centres, block, at[0], normal, col, 1.0)
            _unknown_along(matrix, layout, self.centres, guide, at[0], normal, col, -1.0)

    def per_drive(self, values) -> np.ndarray:
        """Values per drive as (n, k): a scalar or (n,) for one drive, (n, k) or (k,) for k."""
        return np.broadcast_to(np.asarray(values, dtype=float).reshape(-1, self.k)
                               if np.ndim(values) else np.asarray(values, dtype=float), (self.n, self.k))

    def rhs(self, speed=0.0, gravity: bool = True, acceleration=None) -> np.ndarray:
        """The inertia terms at `speed` ((n,), or (n, k) for k drives) (and the known
        `acceleration`, inverse) and, with `gravity`, the weights: m (sum_ij G_ij q_i' q_j'
        [+ sum_j G_j q_j''] - g), I (sum_ij theta_ij q_i' q_j' [+ sum_j theta_j q_j''])."""
        layout = self.layout
        rhs = np.zeros((self.n, layout.size))
        w = self.per_drive(speed)
        ww = w[:, :, None] * w[:, None, :]
        g = np.asarray(self.graph.gravity, dtype=float) if gravity else np.zeros(2)
        qdd = None if acceleration is None else self.per_drive(acceleration)
        for body in self.graph.bodies:
            r = layout.row[body]
            mm, inertia, dc, ddc, dth, ddth = self.rates[body]
            rhs[:, r:r + 2] = mm * (np.sum(ddc * ww[:, None], axis=(2, 3)) - g)
            if body not in self.graph.blocks:
                rhs[:, r + 2] = inertia * np.sum(ddth * ww, axis=(1, 2))
            if qdd is not None:
                rhs[:, r:r + 2] += mm * np.sum(dc * qdd[:, None, :], axis=2)
                if body not in self.graph.blocks:
                    rhs[:, r + 2] += inertia * np.sum(dth * qdd, axis=1)
        return rhs

    def add_loads(self, rhs, loads: Loads) -> None:
        for body, at, force in loads.point_forces:
            _known_force(rhs, self.layout, self.centres, body, at, force)
        for body, couple in loads.couples:
            _known_couple(rhs, self.layout, body, couple)

    def add_drive(self, rhs, torque) -> None:
        """The drives' torques ((n,), or (n, k) for k drives) on the bodies they turn (not the
        held drives': theirs are unknowns)."""
        if self.k == 1:
            _known_couple(rhs, self.layout, self.graph.drive, torque)
            return
        torque = self.per_drive(torque)
        for j, (_, driven) in enumerate(self.graph.driven):
            if j not in self.held:
                _known_couple(rhs, self.layout, driven, torque[:, j])

    def add_pin_friction(self, rhs, name: str, couple) -> None:
        """`couple` on the pin's body acted on, its opposite on the body exerting."""
        _, joint, exerting, acted = next(p for p in self.graph.pins if p[0] == name)
        _known_couple(rhs, self.layout, acted, couple)
        _known_couple(rhs, self.layout, exerting, -couple)

    def add_guide_friction(self, rhs, name: str, along) -> None:
        """`along` (n,) times the guide's direction on the block at its joint, the opposite on
        the guide's body."""
        u, _, at, guide, block = self.guide_dir[name]
        force = np.asarray(along, dtype=float)[:, None] * u
        _known_force(rhs, self.layout, self.centres, block, at[0], force)
        _known_force(rhs, self.layout, self.centres, guide, at[0], -force)

    def rates_at_pins(self, speed) -> tuple[dict, dict]:
        """(pin name -> relative rotation coefficient theta_acted' - theta_exerting', guide name
        -> the block's sliding speed coefficient along +u): times q' the friction's rates."""
        coef = self.coef
        pins = {name: bodies.angle(coef, acted)[1] - bodies.angle(coef, exerting)[1]
                for name, joint, exerting, acted in self.graph.pins}
        guides = {}
        for name, (u, normal, at, guide, block) in self.guide_dir.items():
            p, dp, _ = at
            if guide == bodies.GROUND:
                carried = np.zeros_like(dp)
            elif self.k == 1:
                o, do, _ = coef.origin[guide]
                carried = do + coef.angle[guide][1][:, None] * bodies.perp(p - o)
            else:
                o, do, _ = coef.origin[guide]
                carried = do + coef.angle[guide][1][:, None, :] * bodies.perp(p - o)[..., None]
            slide = dp - carried
            guides[name] = (bodies.dot(slide, u) if self.k == 1
                            else slide[:, 0] * u[:, 0, None] + slide[:, 1] * u[:, 1, None])
        return pins, guides

    def inverse(self) -> _Inverse:
        return _Inverse(self.matrix)

    def unknowns(self, x) -> tuple[dict, dict, np.ndarray]:
        """(pins name -> (n, 2), guides name -> (n, 2) normal force vectors, drive (n,), or
        (n, k) for k drives)."""
        layout = self.layout
        pins = {name: x[:, layout.pin_col[name]:layout.pin_col[name] + 2] for name, *_ in self.graph.pins}
        guides = {name: x[:, layout.guide_col[name], None] * self.guide_dir[name][1]
                  for name, *_ in self.graph.guides}
        if self.k > 1:
            return pins, guides, x[:, list(layout.drive_cols)]
        return pins, guides, x[:, layout.drive_col]


def solve(graph, coef, speed, loads: Loads, *, torque=None, acceleration=None,
          friction: Friction | None = None, held=()) -> BodyForces:
    """The pin and guide forces and the drive's acceleration (given `torque`, (n,) N m) or torque
    (given `acceleration`, (n,) rad/s^2) at rows of the coefficients turning at `speed` (n,); a
    linkage of k drives: (n, k) each, the drives' accelerations or torques; forward, the drives
    `held` (indices) stand still: their acceleration is 0 and `drive` gives their torque."""
    forward = torque is not None
    a = Assembly(graph, coef, forward, held)
    n = a.n
    w = np.broadcast_to(np.asarray(speed, dtype=float), (n,)) if a.k == 1 else a.per_drive(speed)
    rhs = a.rhs(w, acceleration=None if forward else acceleration)
    a.add_loads(rhs, loads)
    if forward:
        a.add_drive(rhs, torque)
    inverse = a.inverse()
    x = inverse.solve(rhs[..., None])[..., 0]
    pin_friction = {name: np.zeros(n) for name, *_ in graph.pins}
    guide_friction = {name: np.zeros(n) for name, *_ in graph.guides}
    converged = np.isfinite(x).all(axis=1)
    if friction is not None and friction.mu > 0:
        x, pin_friction, guide_friction, converged = _with_friction(a, inverse, rhs, x, w, friction)
    pins, guides, drive = a.unknowns(x)
    return BodyForces(pins, guides, drive, pin_friction, guide_friction, converged)


def responses(graph, coef, unit_loads: list) -> tuple[np.ndarray, Assembly]:
    """The pin and guide forces (forward: the drive's torque known) per unit of each load, at the
    rows: (n, 2 pins + guides, K) with columns q'^2 (the inertia terms), gravity and the
    constant loads (`unit_loads[0]`), each of `unit_loads[1:]` (a Loads for a unit force of an
    element), the drive's unit torque, a unit friction couple at each pin, a unit friction force
    along each guide. The forces at any speed and loads are these columns' combination (the
    equations are linear): what the integrator's friction reads from a table."""
    a = Assembly(graph, coef, True)
    n = a.n
    columns = [a.rhs(np.ones(n), gravity=False)]
    constant = a.rhs(np.zeros(n))
    a.add_loads(constant, unit_loads[0])
    columns.append(constant)
    for loads in unit_loads[1:]:
        b = np.zeros((n, a.layout.size))
        a.add_loads(b, loads)
        columns.append(b)
    b = np.zeros((n, a.layout.size))
    a.add_drive(b, np.ones(n))
    columns.append(b)
    for name, *_ in graph.pins:
        b = np.zeros((n, a.layout.size))
        a.add_pin_friction(b, name, np.ones(n))
        columns.append(b)
    for name, *_ in graph.guides:
        b = np.zeros((n, a.layout.size))
        a.add_guide_friction(b, name, np.ones(n))
        columns.append(b)
    b = np.stack(columns, axis=2)
    x = _solve_many(a.matrix, b)
    return x[:, :a.layout.drive_col, :], a


def _solve_many(matrix, rhs):
    """The unknowns for K right-hand sides at once, rhs (n, m, K) (Assembly.solve's rule)."""
    return _Inverse(matrix).solve(rhs)


class _Inverse:
    """The rows' matrices inverted once (their systems are solved several times: friction's
    fixed point, the unit responses); a row whose matrix is near singular (a dead point, its
    condition number beyond 1 / SINGULAR_RCOND) or not finite gives NaN."""

    def __init__(self, matrix) -> None:
        n, m, _ = matrix.shape
        finite = np.isfinite(matrix).all(axis=(1, 2))
        safe = np.where(finite[:, None, None], matrix, np.eye(m))
        with np.errstate(all="ignore"):
            cond = np.linalg.cond(safe)
        self.bad = ~finite | ~(cond < 1.0 / SINGULAR_RCOND)
        safe[self.bad] = np.eye(m)
        self.inverse = np.linalg.inv(safe)

    def solve(self, rhs):
        x = np.einsum("nij,njk->nik", self.inverse, np.where(self.bad[:, None, None], 0.0, rhs))
        bad = self.bad | ~np.isfinite(rhs).all(axis=(1, 2))
        x[bad] = np.nan
        return x


def _unknown_force(matrix, layout, centres, body, at, col, sign) -> None:
    """An unknown force (columns col, col + 1) acting with `sign` on `body` at `at`."""
    if body == bodies.GROUND:
        return
    r = layout.row[body]
    matrix[:, r, col] += sign
    matrix[:, r + 1, col + 1] += sign
    if body in layout.graph.blocks:
        return
    lever = at - centres[body]
    matrix[:, r + 2, col] += -sign * lever[:, 1]
    matrix[:, r + 2, col + 1] += sign * lever[:, 0]


def _unknown_along(matrix, layout, centres, body, at, direction, col, sign) -> None:
    """An unknown scalar (column col) times `direction` acting with `sign` on `body` at `at`."""
    if body == bodies.GROUND:
        return
    r = layout.row[body]
    matrix[:, r, col] += sign * direction[:, 0]
    matrix[:, r + 1, col] += sign * direction[:, 1]
    if body in layout.graph.blocks:
        return
    matrix[:, r + 2, col] += sign * bodies.cross(at - centres[body], direction)


def _known_force(rhs, layout, centres, body, at, force) -> None:
    if body == bodies.GROUND:
        return
    r = layout.row[body]
    force = np.broadcast_to(np.asarray(force, dtype=float), at.shape)
    rhs[:, r:r + 2] -= force
    if body not in layout.graph.blocks:
        rhs[:, r + 2] -= bodies.cross(at - centres[body], force)


def _known_couple(rhs, layout, body, couple) -> None:
    if body == bodies.GROUND or body in layout.graph.blocks:
        return
    rhs[:, layout.row[body] + 2] -= couple


def _rate(coefficient, w):
    """A rate from its coefficients and the drives' speeds: c w (one drive), sum_j c_j w_j."""
    return coefficient * w if np.ndim(coefficient) == 1 else np.sum(coefficient * w, axis=1)


def _with_friction(a: Assembly, inverse, rhs, x, w, friction):
    """Fixed-point iteration of the friction couples and forces (module docstring)."""
    graph, layout = a.graph, a.layout
    n = len(w)
    pin_rate, guide_rate = a.rates_at_pins(w)
    rel = {name: smooth_sign(_rate(rate, w), friction.eps) for name, rate in pin_rate.items()}
    slide = {name: smooth_sign(_rate(rate, w), friction.eps_v) for name, rate in guide_rate.items()}
    scale = np.nanmax(np.abs(x), axis=1, initial=0.0)
    done = np.zeros(n, dtype=bool)
    last = np.full(n, np.inf)
    pin_friction, guide_friction = {}, {}
    for _ in range(FRICTION_ITERATIONS):
        b = rhs.copy()
        for name, *_ in graph.pins:
            col = layout.pin_col[name]
            couple = -friction.mu * friction.radii[name] * np.hypot(x[:, col], x[:, col + 1]) * rel[name]
            pin_friction[name] = couple
            a.add_pin_friction(b, name, couple)
        for name, *_ in graph.guides:
            along = -friction.mu * np.abs(x[:, layout.guide_col[name]]) * slide[name]
            guide_friction[name] = along
            a.add_guide_friction(b, name, along)
        new = inverse.solve(b[..., None])[..., 0]
        change = np.nanmax(np.abs(new - x), axis=1, initial=0.0)
        scale = np.maximum(scale, np.nanmax(np.abs(new), axis=1, initial=0.0))
        x = new
        floor = np.maximum(scale, 1e-300)
        settled = (change <= FRICTION_RTOL * floor) | ((change <= FRICTION_STALL * floor) & (change >= last))
        done = np.isfinite(x).all(axis=1) & settled
        last = change
        if done.all():
            break
    x = np.where(done[:, None], x, np.nan)
    return x, pin_friction, guide_friction, done
