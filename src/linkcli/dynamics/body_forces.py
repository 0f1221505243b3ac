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
rows), until the forces change by less than FRICTION_RTOL of their scale; a row that does not
converge in FRICTION_ITERATIONS passes (friction locks the linkage) is NaN.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from linkcli.dynamics import bodies

FRICTION_RTOL = 1e-13
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
        if col + 1 != m:
            raise ValueError(f"the body graph is not square: {m} equations, {col + 1} unknowns")


def solve(graph, coef, speed, loads: Loads, *, torque=None, acceleration=None,
          friction: Friction | None = None) -> BodyForces:
    """The pin and guide forces and the drive's acceleration (given `torque`, (n,) N m) or torque
    (given `acceleration`, (n,) rad/s^2) at rows of the coefficients turning at `speed` (n,)."""
    layout = Layout(graph)
    n = len(coef.q)
    m = layout.size
    w = np.broadcast_to(np.asarray(speed, dtype=float), (n,))
    w2 = w * w
    matrix = np.zeros((n, m, m))
    rhs = np.zeros((n, m))
    g = np.asarray(graph.gravity, dtype=float)
    forward = torque is not None
    qdd = None if forward else np.broadcast_to(np.asarray(acceleration, dtype=float), (n,))
    centres = {}
    for body in graph.bodies:
        r = layout.row[body]
        mass = graph.masses.get(body)
        mm = 0.0 if mass is None else mass.mass
        inertia = 0.0 if mass is None or body in graph.blocks else mass.inertia
        c, dc, ddc = bodies.centre(graph, coef, body)
        centres[body] = c
        _, dth, ddth = coef.angle[body]
        rhs[:, r:r + 2] = mm * (ddc * w2[:, None] - g)
        if forward:
            matrix[:, r:r + 2, layout.drive_col] = -mm * dc
        else:
            rhs[:, r:r + 2] += mm * dc * qdd[:, None]
        if body not in graph.blocks:
            rhs[:, r + 2] = inertia * ddth * w2
            if forward:
                matrix[:, r + 2, layout.drive_col] = -inertia * dth
            else:
                rhs[:, r + 2] += inertia * dth * qdd
    if forward:
        _known_couple(rhs, layout, graph.drive, torque)
    else:
        matrix[:, layout.row[graph.drive] + 2, layout.drive_col] = 1.0
    for body, at, force in loads.point_forces:
        _known_force(rhs, layout, centres, body, at, force)
    for body, couple in loads.couples:
        _known_couple(rhs, layout, body, couple)
    joint_at = {}
    for name, joint, exerting, acted in graph.pins:
        at = bodies.point(graph, coef, joint)[0]
        joint_at[joint] = at
        col = layout.pin_col[name]
        _unknown_force(matrix, layout, centres, acted, at, col, 1.0)
        _unknown_force(matrix, layout, centres, exerting, at, col, -1.0)
    guide_dir = {}
    for name, joint, guide, block, local in graph.guides:
        at = bodies.point(graph, coef, joint)
        theta = bodies.angle(coef, guide)[0]
        u = bodies.rotated(np.asarray(local, dtype=float), theta)
        normal = bodies.perp(u)
        guide_dir[name] = (u, normal, at, guide, block)
        col = layout.guide_col[name]
        _unknown_along(matrix, layout, centres, block, at[0], normal, col, 1.0)
        _unknown_along(matrix, layout, centres, guide, at[0], normal, col, -1.0)
    x = _solve(matrix, rhs)
    pin_friction = {name: np.zeros(n) for name, *_ in graph.pins}
    guide_friction = {name: np.zeros(n) for name, *_ in graph.guides}
    converged = np.isfinite(x).all(axis=1)
    if friction is not None and friction.mu > 0:
        x, pin_friction, guide_friction, converged = _with_friction(
            graph, coef, layout, matrix, rhs, x, w, centres, joint_at, guide_dir, friction)
    pins = {name: x[:, layout.pin_col[name]:layout.pin_col[name] + 2] for name, *_ in graph.pins}
    guides = {name: x[:, layout.guide_col[name], None] * guide_dir[name][1] for name, *_ in graph.guides}
    return BodyForces(pins, guides, x[:, layout.drive_col], pin_friction, guide_friction, converged)


def _solve(matrix, rhs):
    """One batched solve; rows whose matrix is near singular (a dead point) or not finite: NaN."""
    n, m, _ = matrix.shape
    finite = np.isfinite(matrix).all(axis=(1, 2)) & np.isfinite(rhs).all(axis=1)
    safe = np.where(finite[:, None, None], matrix, np.eye(m))
    with np.errstate(all="ignore"):
        cond = np.linalg.cond(safe)
    bad = ~finite | ~(cond < 1.0 / SINGULAR_RCOND)
    safe[bad] = np.eye(m)
    x = np.linalg.solve(safe, np.where(bad[:, None], 0.0, rhs)[..., None])[..., 0]
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


def _with_friction(graph, coef, layout, matrix, rhs, x, w, centres, joint_at, guide_dir, friction):
    """Fixed-point iteration of the friction couples and forces (module docstring)."""
    n = len(w)
    rel = {}
    for name, joint, exerting, acted in graph.pins:
        rate = bodies.angle(coef, acted)[1] - bodies.angle(coef, exerting)[1]
        rel[name] = smooth_sign(rate * w, friction.eps)
    slide = {}
    for name, (u, normal, at, guide, block) in guide_dir.items():
        p, dp, _ = at
        if guide == bodies.GROUND:
            carried = np.zeros_like(dp)
        else:
            o, do, _ = coef.origin[guide]
            _, dth, _ = coef.angle[guide]
            carried = do + dth[:, None] * bodies.perp(p - o)
        slide[name] = smooth_sign(bodies.dot(dp - carried, u) * w, friction.eps_v)
    scale = np.nanmax(np.abs(x), axis=1, initial=0.0)
    done = np.zeros(n, dtype=bool)
    pin_friction = {}
    guide_friction = {}
    for _ in range(FRICTION_ITERATIONS):
        b = rhs.copy()
        for name, joint, exerting, acted in graph.pins:
            col = layout.pin_col[name]
            size = np.hypot(x[:, col], x[:, col + 1])
            couple = -friction.mu * friction.radii[name] * size * rel[name]  # on the body acted on
            pin_friction[name] = couple
            _known_couple(b, layout, acted, couple)
            _known_couple(b, layout, exerting, -couple)
        for name, (u, normal, at, guide, block) in guide_dir.items():
            size = np.abs(x[:, layout.guide_col[name]])
            along = -friction.mu * size * slide[name]  # on the block, along +u
            guide_friction[name] = along
            force = along[:, None] * u
            _known_force(b, layout, centres, block, at[0], force)
            _known_force(b, layout, centres, guide, at[0], -force)
        new = _solve(matrix, b)
        change = np.nanmax(np.abs(new - x), axis=1, initial=0.0)
        scale = np.maximum(scale, np.nanmax(np.abs(new), axis=1, initial=0.0))
        x = new
        done = np.isfinite(x).all(axis=1) & (change <= FRICTION_RTOL * np.maximum(scale, 1e-300))
        if done.all():
            break
    x = np.where(done[:, None], x, np.nan)
    return x, pin_friction, guide_friction, done
