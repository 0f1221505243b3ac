"""The Newton-Euler kit every mechanism's loads are written with (kineto-statics).

Inverse dynamics: the motion is given (a kinematic state per row), the forces that produce it
are unknown. Each moving link obeys Newton-Euler about its centre G:

    sum F = m a_G,        sum (Q - G) x F_Q + sum T = I_G alpha

A home stacks its links' equations for all rows into one (n, k, k) array and solves it once
(`solve`). Source: Norton, Design of Machinery, ch. 11 (dynamic force analysis, the four-bar's
matrix form); Uicker, Pennock & Shigley, Theory of Machines and Mechanisms, ch. 14-15.
Units: SI inside (m, kg, N, N m, rad/s, rad/s^2, kg m^2); positions in the global frame.

`fill_input_and_coupler` writes the first two links of a chain that starts with a crank A0-A
and a coupler A-B (the four-bar's and the slider-crank's): rows 0-5, unknowns A0 (0, 1),
A (2, 3), B (4, 5) and the drive's torque in `torque_column`.
"""

from __future__ import annotations

import numpy as np

from linkcli.model import LinkMass, Loads

SINGULAR_TOLERANCE = 1e-9
"""A row is singular (dead point: the system has no unique solution) when the sine of the angle
between the two links that meet there is below this; the mechanical advantage is infinite
(a toggle) when the sine between input and coupler is below it. Dimensionless, so scale-free."""

# Round-off: forces below linkcli.noise.NOISE_FLOOR x force_scale (torques below it x
# torque_scale) are reported as 0 by `forces_rows` and `load_cycle`; the torque's peak ties
# within linkcli.noise.TIE go to the first row in sweep order (noise.first_max).


def points(value, n: int | None = None) -> np.ndarray:
    """(n, 2) rows of points from (n, 2) or one (2,) point broadcast to n rows."""
    array = np.asarray(value, dtype=float)
    if array.shape[-1:] != (2,):
        raise ValueError(f"expected points of shape (n, 2) or (2,), got {array.shape}")
    return array if n is None else np.broadcast_to(array, (n, 2))


def unit_angle(angle) -> np.ndarray:
    angle = np.asarray(angle, dtype=float)
    return np.stack([np.cos(angle), np.sin(angle)], axis=-1)


def cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """z component of u x v for rows of 2-vectors."""
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def perp(u: np.ndarray) -> np.ndarray:
    """u rotated by +90 deg: k x u."""
    return np.stack([-u[..., 1], u[..., 0]], axis=-1)


def in_frame(origin, x_towards, local) -> np.ndarray:
    """Global position of `local` (2,) in the frame at `origin` with x along origin -> x_towards."""
    axis = x_towards - origin
    axis = axis / np.linalg.norm(axis, axis=-1, keepdims=True)
    local = np.asarray(local, dtype=float)
    return origin + local[0] * axis + local[1] * perp(axis)


def point_acceleration(origin_acceleration, lever, omega, alpha) -> np.ndarray:
    """a_Q = a_O + alpha x r - omega^2 r, r = Q - O (rigid body, plane motion)."""
    return (origin_acceleration + alpha[:, None] * perp(lever)
            - (omega ** 2)[:, None] * lever)


NO_MASS = LinkMass(0.0)


def add_force(matrix, row, column, lever, sign=1.0):
    """Moment row: sign * (lever x F) for the unknown force F in columns column, column + 1."""
    matrix[:, row, column] += -sign * lever[:, 1]
    matrix[:, row, column + 1] += sign * lever[:, 0]


def body(mass: LinkMass | None, origin, x_towards):
    """(mass, inertia, centre G (n, 2)) of a link whose frame is origin -> x_towards."""
    mass = mass or NO_MASS
    return mass.mass, mass.inertia, in_frame(origin, x_towards, mass.center)


def coupler_load(state, loads: Loads):
    force = np.asarray(loads.coupler_force, dtype=float)
    if force.shape != (2,):
        raise ValueError(f"coupler_force must be two numbers, got {loads.coupler_force!r}")
    if state.P is None and np.any(force != 0):
        raise ValueError("a coupler force needs a coupler point")
    return force, (state.A if state.P is None else state.P)


def fill_input_and_coupler(matrix, rhs, state, loads, masses, torque_column):
    """Rows 0-5: input link (A0, -A, T_in) and coupler (A, -B, coupler force)."""
    n = state.rows
    gravity = np.asarray(loads.gravity, dtype=float)
    force, point = coupler_load(state, loads)
    zero = np.zeros(n)
    w2, a2 = state.omega_input, state.alpha_input
    w3, a3 = state.omega_coupler, state.alpha_coupler

    m2, i2, g2 = body(masses.input, state.A0, state.A)
    acc_g2 = point_acceleration(zero[:, None], g2 - state.A0, w2, a2)
    acc_a = point_acceleration(zero[:, None], state.A - state.A0, w2, a2)
    for k in range(2):
        matrix[:, k, k] = 1.0            # A0 on input
        matrix[:, k, 2 + k] = -1.0       # coupler on input = -A
        rhs[:, k] = m2 * (acc_g2[:, k] - gravity[k])
    add_force(matrix, 2, 0, state.A0 - g2)
    add_force(matrix, 2, 2, state.A - g2, -1.0)
    matrix[:, 2, torque_column] = 1.0
    rhs[:, 2] = i2 * a2

    m3, i3, g3 = body(masses.coupler, state.A, state.B)
    acc_g3 = point_acceleration(acc_a, g3 - state.A, w3, a3)
    for k in range(2):
        matrix[:, 3 + k, 2 + k] = 1.0    # input on coupler = A
        matrix[:, 3 + k, 4 + k] = -1.0   # output (slider) on coupler = -B
        rhs[:, 3 + k] = m3 * (acc_g3[:, k] - gravity[k]) - force[k]
    add_force(matrix, 5, 2, state.A - g3)
    add_force(matrix, 5, 4, state.B - g3, -1.0)
    rhs[:, 5] = i3 * a3 - cross(point - g3, np.broadcast_to(force, (n, 2)))
    acc_b = point_acceleration(acc_a, state.B - state.A, w3, a3)
    scale_terms = [np.abs(force).sum(), m2 * np.abs(gravity).sum(),
                   m3 * np.abs(gravity).sum(), m2 * max_norm(acc_g2), m3 * max_norm(acc_g3)]
    length = max(max_norm(state.A - state.A0), max_norm(state.B - state.A),
                 max_norm(point - state.A))
    inertia_terms = [i2 * finite_max(a2), i3 * finite_max(a3)]
    return acc_b, scale_terms, inertia_terms, length


def finite_max(values) -> float:
    """Largest finite |value| (0 if none): a scale that singular rows cannot spoil."""
    values = np.abs(np.asarray(values, dtype=float))
    return float(np.max(values[np.isfinite(values)], initial=0.0))


def max_norm(vectors) -> float:
    return finite_max(np.hypot(vectors[:, 0], vectors[:, 1]))


def solve(matrix, rhs, singular):
    """One batched solve; singular rows get an identity system and NaN results."""
    matrix[singular] = np.eye(matrix.shape[-1])
    solution = np.linalg.solve(matrix, rhs[..., None])[..., 0]
    solution[singular] = np.nan
    return solution


def scales(force_terms, inertia_terms, torque, length):
    length = length if length > 0 else 1.0
    force_scale = float(sum(force_terms) + (abs(torque) + sum(inertia_terms)) / length)
    return force_scale, force_scale * length



def mechanical_advantage(state, numerator) -> np.ndarray:
    """Static mechanical advantage per row, velocity-ratio form, NaN at a toggle (infinite):
    MA = numerator / ((A - A0) x (B - A)), the numerator the home's (Norton, ch. 6,
    mechanical advantage: omega_in over the output's rate; by virtual work the output's load
    over the input torque). Toggle: input and coupler collinear,
    |sin(theta3 - theta2)| <= SINGULAR_TOLERANCE."""
    with np.errstate(all="ignore"):
        crank, coupler = state.A - state.A0, state.B - state.A
        denominator = cross(crank, coupler)
        toggle = ~(np.abs(denominator) > SINGULAR_TOLERANCE * np.linalg.norm(crank, axis=1)
                   * np.linalg.norm(coupler, axis=1))
        return np.where(toggle, np.nan, numerator / np.where(toggle, 1.0, denominator))


def in_metres(masses, scale: float):
    """The masses (model.Masses) with their centres in metres (they are in the file's
    length unit; `scale` metres per unit)."""
    from dataclasses import fields, replace
    def one(m: LinkMass | None):
        return None if m is None else LinkMass(m.mass, (m.center[0] * scale, m.center[1] * scale), m.inertia)
    return replace(masses, **{f.name: one(getattr(masses, f.name)) for f in fields(masses) if f.name != "named"},
                   named=tuple((name, one(m)) for name, m in masses.named))


# ---------------------------------------------------------------- loads on each link (strength)
def link_load(name: str, at, force=None, couple=None):
    """A protocol.LinkLoad at the (n, 2) points `at` (m): `force` (n, 2) N (default 0) and
    `couple` (n,) N m (default 0), broadcast to the rows."""
    from linkcli.mechanisms.protocol import LinkLoad
    at = np.asarray(at, dtype=float)
    n = len(at)
    force = np.zeros((n, 2)) if force is None else np.broadcast_to(np.asarray(force, dtype=float), (n, 2))
    couple = np.zeros(n) if couple is None else np.broadcast_to(np.asarray(couple, dtype=float), (n,))
    return LinkLoad(name, at, force, couple)


def inertia_loads(mass: LinkMass | None, origin, x_towards, origin_acceleration, omega, alpha,
                  gravity) -> tuple:
    """The weight and d'Alembert inertia of a link's mass as one load at its centre G:
    force m (g - a_G), couple -I_G alpha (Norton, Design of Machinery, ch. 11); () for a
    massless link. Its frame runs from `origin` towards `x_towards`, whose acceleration is
    `origin_acceleration` ((n, 2) m/s^2, 0 for a ground pivot)."""
    if mass is None or (mass.mass == 0 and mass.inertia == 0):
        return ()
    m, i, g = body(mass, origin, x_towards)
    acc = point_acceleration(np.broadcast_to(np.asarray(origin_acceleration, dtype=float), g.shape),
                             g - origin, omega, alpha)
    force = m * (np.asarray(gravity, dtype=float) - acc)
    return (link_load("inertia", g, force, -i * np.asarray(alpha, dtype=float)),)


def input_and_coupler_members(state, loads: Loads, masses, rows) -> tuple[tuple, tuple]:
    """The loads on the first two links of a chain A0 - A - B (the links of
    `fill_input_and_coupler`), from the pin forces of `rows`: the input A0 -> A (pin A0, the
    coupler's -A, the drive's torque at A0, its mass) and the coupler A -> B (pin A, the
    output's -B, the coupler force at P, its mass)."""
    pins, n = rows.pins, state.rows
    acc_a = point_acceleration(np.zeros((n, 2)), state.A - state.A0, state.omega_input,
                               state.alpha_input)
    coupler_force = ()
    if any(loads.coupler_force):
        coupler_force = (link_load("coupler_force", state.A if state.P is None else state.P,
                                   loads.coupler_force),)
    input_link = (link_load("A0", state.A0, pins["A0"]), link_load("A", state.A, -pins["A"]),
                  link_load("drive", state.A0, couple=rows.input_torque),
                  *inertia_loads(masses.input, state.A0, state.A, 0.0, state.omega_input,
                                 state.alpha_input, loads.gravity))
    coupler = (link_load("A", state.A, pins["A"]), link_load("B", state.B, -pins["B"]), *coupler_force,
               *inertia_loads(masses.coupler, state.A, state.B, acc_a, state.omega_coupler,
                              state.alpha_coupler, loads.gravity))
    return input_link, coupler
