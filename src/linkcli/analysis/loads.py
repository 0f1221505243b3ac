"""Loads on a four-bar or a slider-crank: input torque, pin forces, mechanical advantage.

Inverse dynamics (kineto-statics): the motion is given (a kinematic state per row), the
forces that produce it are unknown. Each moving link obeys Newton-Euler about its centre G:

    sum F = m a_G,        sum (Q - G) x F_Q + sum T = I_G alpha

Four-bar, three links x three equations = 9 equations per row, 9 unknowns
[A0x, A0y, Ax, Ay, Bx, By, B0x, B0y, T_in]; slider-crank, crank 3 + rod 3 + slider 2 = 8
equations, 8 unknowns [A0x, A0y, Ax, Ay, Bx, By, N, T_in]. All rows are stacked into one
(n, 9, 9) (or (n, 8, 8)) array and solved by one batched np.linalg.solve.
Source: Norton, Design of Machinery, ch. 11 (dynamic force analysis, the four-bar's matrix
form); Uicker, Pennock & Shigley, Theory of Machines and Mechanisms, ch. 14-15.

Sign conventions (every force acts on the link named second):
    A0    ground  -> input           B     coupler -> output (slider-crank: rod -> slider)
    A     input   -> coupler         B0    ground  -> output
    guide the guide's normal force on the slider (along +y; the guide is frictionless, along x)
    T_in  the drive's torque on the input link, counter-clockwise positive.
The reaction on the other link is the opposite force (Newton's third law).

Units: SI inside (m, kg, N, N m, rad/s, rad/s^2, kg m^2); positions in the global frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from linkcli.model import LinkMass, Loads, Masses  # the problem's load case (re-exported)
from linkcli.noise import first_max, snap

__all__ = ["FourBarState", "SliderCrankState", "LinkMass", "Masses", "Loads", "LoadRows",
           "four_bar_loads", "slider_crank_loads", "mechanical_advantage", "forces_rows",
           "load_cycle"]

SINGULAR_TOLERANCE = 1e-9
"""A row is singular (dead point: the system has no unique solution) when the sine of the angle
between the two links that meet there is below this; the mechanical advantage is infinite
(a toggle) when the sine between input and coupler is below it. Dimensionless, so scale-free."""

# Round-off: forces below linkcli.noise.NOISE_FLOOR x force_scale (torques below it x
# torque_scale) are reported as 0 by `forces_rows` and `load_cycle`; the torque's peak ties
# within linkcli.noise.TIE go to the first row in sweep order (noise.first_max).


def _points(value, n: int | None = None) -> np.ndarray:
    points = np.asarray(value, dtype=float)
    if points.shape[-1:] != (2,):
        raise ValueError(f"expected points of shape (n, 2) or (2,), got {points.shape}")
    return points if n is None else np.broadcast_to(points, (n, 2))


def _unit_angle(angle) -> np.ndarray:
    angle = np.asarray(angle, dtype=float)
    return np.stack([np.cos(angle), np.sin(angle)], axis=-1)


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """z component of u x v for rows of 2-vectors."""
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def _perp(u: np.ndarray) -> np.ndarray:
    """u rotated by +90 deg: k x u."""
    return np.stack([-u[..., 1], u[..., 0]], axis=-1)


def _in_frame(origin, x_towards, local) -> np.ndarray:
    """Global position of `local` (2,) in the frame at `origin` with x along origin -> x_towards."""
    axis = x_towards - origin
    axis = axis / np.linalg.norm(axis, axis=-1, keepdims=True)
    local = np.asarray(local, dtype=float)
    return origin + local[0] * axis + local[1] * _perp(axis)


def _point_acceleration(origin_acceleration, lever, omega, alpha) -> np.ndarray:
    """a_Q = a_O + alpha x r - omega^2 r, r = Q - O (rigid body, plane motion)."""
    return (origin_acceleration + alpha[:, None] * _perp(lever)
            - (omega ** 2)[:, None] * lever)


@dataclass(frozen=True)
class FourBarState:
    """Kinematic state of a four-bar, one row per position (n rows), SI, global frame.

    A0, A, B, B0, P: (n, 2) points (A0, B0 may be (2,), P may be None: no coupler point);
    omega_*: angular velocities (rad/s), alpha_*: angular accelerations (rad/s^2), (n,), CCW +.
    The ground pivots are fixed.
    """

    A0: np.ndarray
    A: np.ndarray
    B: np.ndarray
    B0: np.ndarray
    omega_input: np.ndarray
    omega_coupler: np.ndarray
    omega_output: np.ndarray
    alpha_input: np.ndarray
    alpha_coupler: np.ndarray
    alpha_output: np.ndarray
    P: np.ndarray | None = None

    def __post_init__(self) -> None:
        n = len(_points(self.A))
        for name in ("A0", "A", "B", "B0") + (("P",) if self.P is not None else ()):
            object.__setattr__(self, name, _points(getattr(self, name), n))
        for name in ("omega_input", "omega_coupler", "omega_output",
                     "alpha_input", "alpha_coupler", "alpha_output"):
            object.__setattr__(self, name, np.broadcast_to(
                np.asarray(getattr(self, name), dtype=float), (n,)))

    @property
    def rows(self) -> int:
        return len(self.A)

    @classmethod
    def from_angles(cls, *, ground_length, input_length, coupler_length, output_length,
                    phi, psi, omega_input, omega_coupler, omega_output,
                    alpha_input=0.0, alpha_coupler=0.0, alpha_output=0.0,
                    coupler_point=None, ground_pivot=(0.0, 0.0), ground_angle=0.0):
        """State from the conventions of docs/format.md's angles (local frame, radians) and lengths in metres.

        A0 = ground_pivot, B0 = A0 + d e(gamma), A = A0 + a e(gamma + phi),
        B = B0 + c e(gamma + psi); P from `coupler_point` (m) in the coupler frame
        (the coupler's direction follows from A and B).
        """
        phi = np.atleast_1d(np.asarray(phi, dtype=float))
        a0 = np.asarray(ground_pivot, dtype=float)
        b0 = a0 + ground_length * _unit_angle(ground_angle)
        a = a0 + input_length * _unit_angle(ground_angle + phi)
        b = b0 + output_length * _unit_angle(ground_angle + np.asarray(psi, dtype=float))
        p = None if coupler_point is None else _in_frame(a, b, coupler_point)
        return cls(a0, a, b, b0, omega_input, omega_coupler, omega_output,
                   alpha_input, alpha_coupler, alpha_output, p)


@dataclass(frozen=True)
class SliderCrankState:
    """Kinematic state of a slider-crank, one row per position (n rows), SI, global frame.

    A0 crank pivot, A crank pin, B slider pin ((n, 2); A0 may be (2,)), P optional coupler
    point on the rod. The guide is along +x. The slider's acceleration is that of B as a
    point of the rod (its x component: the guide carries the rest).
    """

    A0: np.ndarray
    A: np.ndarray
    B: np.ndarray
    omega_input: np.ndarray
    omega_coupler: np.ndarray
    alpha_input: np.ndarray
    alpha_coupler: np.ndarray
    P: np.ndarray | None = None

    def __post_init__(self) -> None:
        n = len(_points(self.A))
        for name in ("A0", "A", "B") + (("P",) if self.P is not None else ()):
            object.__setattr__(self, name, _points(getattr(self, name), n))
        for name in ("omega_input", "omega_coupler", "alpha_input", "alpha_coupler"):
            object.__setattr__(self, name, np.broadcast_to(
                np.asarray(getattr(self, name), dtype=float), (n,)))

    @property
    def rows(self) -> int:
        return len(self.A)

    @classmethod
    def from_angles(cls, *, input_length, coupler_length, phi, theta, omega_input,
                    omega_coupler, alpha_input=0.0, alpha_coupler=0.0, coupler_point=None):
        """State from the file format's slider-crank frame: A0 at the origin, A = a e(phi),
        B = A + b e(theta) (on the axis y = offset), lengths in metres, angles in radians."""
        phi = np.atleast_1d(np.asarray(phi, dtype=float))
        a = input_length * _unit_angle(phi)
        b = a + coupler_length * _unit_angle(theta)
        p = None if coupler_point is None else _in_frame(a, b, coupler_point)
        return cls(np.zeros(2), a, b, omega_input, omega_coupler, alpha_input,
                   alpha_coupler, p)


NO_MASS = LinkMass(0.0)


@dataclass(frozen=True)
class LoadRows:
    """Solution per row: input_torque (n,) N m; pins {name: (n, 2) N}; singular (n,) bool
    (dead point: forces NaN); mechanical_advantage (n,) (NaN at a toggle: infinite);
    force_scale (N) and torque_scale (N m) for the noise floor."""

    input_torque: np.ndarray
    pins: dict[str, np.ndarray]
    singular: np.ndarray
    mechanical_advantage: np.ndarray
    force_scale: float
    torque_scale: float
    pin_names: tuple[str, ...] = field(default=())

    def magnitude(self, pin: str) -> np.ndarray:
        return np.hypot(self.pins[pin][:, 0], self.pins[pin][:, 1])


def _add_force(matrix, row, column, lever, sign=1.0):
    """Moment row: sign * (lever x F) for the unknown force F in columns column, column + 1."""
    matrix[:, row, column] += -sign * lever[:, 1]
    matrix[:, row, column + 1] += sign * lever[:, 0]


def _body(mass: LinkMass | None, origin, x_towards):
    """(mass, inertia, centre G (n, 2)) of a link whose frame is origin -> x_towards."""
    mass = mass or NO_MASS
    return mass.mass, mass.inertia, _in_frame(origin, x_towards, mass.center)


def _coupler_load(state, loads: Loads):
    force = np.asarray(loads.coupler_force, dtype=float)
    if force.shape != (2,):
        raise ValueError(f"coupler_force must be two numbers, got {loads.coupler_force!r}")
    if state.P is None and np.any(force != 0):
        raise ValueError("a coupler force needs a coupler point")
    return force, (state.A if state.P is None else state.P)


def _fill_input_and_coupler(matrix, rhs, state, loads, masses, torque_column):
    """Rows 0-5: input link (A0, -A, T_in) and coupler (A, -B, coupler force)."""
    n = state.rows
    gravity = np.asarray(loads.gravity, dtype=float)
    force, point = _coupler_load(state, loads)
    zero = np.zeros(n)
    w2, a2 = state.omega_input, state.alpha_input
    w3, a3 = state.omega_coupler, state.alpha_coupler

    m2, i2, g2 = _body(masses.input, state.A0, state.A)
    acc_g2 = _point_acceleration(zero[:, None], g2 - state.A0, w2, a2)
    acc_a = _point_acceleration(zero[:, None], state.A - state.A0, w2, a2)
    for k in range(2):
        matrix[:, k, k] = 1.0            # A0 on input
        matrix[:, k, 2 + k] = -1.0       # coupler on input = -A
        rhs[:, k] = m2 * (acc_g2[:, k] - gravity[k])
    _add_force(matrix, 2, 0, state.A0 - g2)
    _add_force(matrix, 2, 2, state.A - g2, -1.0)
    matrix[:, 2, torque_column] = 1.0
    rhs[:, 2] = i2 * a2

    m3, i3, g3 = _body(masses.coupler, state.A, state.B)
    acc_g3 = _point_acceleration(acc_a, g3 - state.A, w3, a3)
    for k in range(2):
        matrix[:, 3 + k, 2 + k] = 1.0    # input on coupler = A
        matrix[:, 3 + k, 4 + k] = -1.0   # output (slider) on coupler = -B
        rhs[:, 3 + k] = m3 * (acc_g3[:, k] - gravity[k]) - force[k]
    _add_force(matrix, 5, 2, state.A - g3)
    _add_force(matrix, 5, 4, state.B - g3, -1.0)
    rhs[:, 5] = i3 * a3 - _cross(point - g3, np.broadcast_to(force, (n, 2)))
    acc_b = _point_acceleration(acc_a, state.B - state.A, w3, a3)
    scale_terms = [np.abs(force).sum(), m2 * np.abs(gravity).sum(),
                   m3 * np.abs(gravity).sum(), m2 * _max_norm(acc_g2), m3 * _max_norm(acc_g3)]
    length = max(_max_norm(state.A - state.A0), _max_norm(state.B - state.A),
                 _max_norm(point - state.A))
    inertia_terms = [i2 * _finite_max(a2), i3 * _finite_max(a3)]
    return acc_b, scale_terms, inertia_terms, length


def _finite_max(values) -> float:
    """Largest finite |value| (0 if none): a scale that singular rows cannot spoil."""
    values = np.abs(np.asarray(values, dtype=float))
    return float(np.max(values[np.isfinite(values)], initial=0.0))


def _max_norm(vectors) -> float:
    return _finite_max(np.hypot(vectors[:, 0], vectors[:, 1]))


def _solve(matrix, rhs, singular):
    """One batched solve; singular rows get an identity system and NaN results."""
    matrix[singular] = np.eye(matrix.shape[-1])
    solution = np.linalg.solve(matrix, rhs[..., None])[..., 0]
    solution[singular] = np.nan
    return solution


def _scales(force_terms, inertia_terms, torque, length):
    length = length if length > 0 else 1.0
    force_scale = float(sum(force_terms) + (abs(torque) + sum(inertia_terms)) / length)
    return force_scale, force_scale * length


def four_bar_loads(state: FourBarState, loads: Loads = Loads(),
                   masses: Masses = Masses()) -> LoadRows:
    """Input torque and pin forces of a four-bar at every row (one (n, 9, 9) solve).

    Output link rows 6-8: B + B0 = m4 (a_G4 - g); (B - G4) x B + (B0 - G4) x B0 + T_out
    = I4 alpha4. Singular where coupler and output are collinear (|sin| <= SINGULAR_TOLERANCE).
    """
    n = state.rows
    matrix = np.zeros((n, 9, 9))
    rhs = np.zeros((n, 9))
    with np.errstate(all="ignore"):
        _, force_terms, inertia_terms, length = _fill_input_and_coupler(
            matrix, rhs, state, loads, masses, 8)
        gravity = np.asarray(loads.gravity, dtype=float)
        m4, i4, g4 = _body(masses.output, state.B0, state.B)
        acc_g4 = _point_acceleration(np.zeros((n, 1)), g4 - state.B0,
                                     state.omega_output, state.alpha_output)
        for k in range(2):
            matrix[:, 6 + k, 4 + k] = 1.0    # coupler on output = B
            matrix[:, 6 + k, 6 + k] = 1.0    # ground on output = B0
            rhs[:, 6 + k] = m4 * (acc_g4[:, k] - gravity[k])
        _add_force(matrix, 8, 4, state.B - g4)
        _add_force(matrix, 8, 6, state.B0 - g4)
        rhs[:, 8] = i4 * state.alpha_output - loads.output_torque
        coupler, output = state.B - state.A, state.B - state.B0
        sine = _cross(coupler, output) / (np.linalg.norm(coupler, axis=1)
                                          * np.linalg.norm(output, axis=1))
        singular = ~(np.abs(sine) > SINGULAR_TOLERANCE)
        solution = _solve(matrix, rhs, singular)
        force_terms += [m4 * np.abs(gravity).sum(), m4 * _max_norm(acc_g4)]
        inertia_terms.append(i4 * _finite_max(state.alpha_output))
        length = max(length, _max_norm(output))
        force_scale, torque_scale = _scales(force_terms, inertia_terms,
                                            loads.output_torque, length)
        pins = {name: solution[:, 2 * k:2 * k + 2]
                for k, name in enumerate(("A0", "A", "B", "B0"))}
        return LoadRows(solution[:, 8], pins, singular, mechanical_advantage(state),
                        force_scale, torque_scale, ("A0", "A", "B", "B0"))


def slider_crank_loads(state: SliderCrankState, loads: Loads = Loads(),
                       masses: Masses = Masses()) -> LoadRows:
    """Input torque, pin forces and guide force of a slider-crank (one (n, 8, 8) solve).

    Slider rows 6-7 (frictionless guide along x, slider mass m4 = masses.output.mass):
    Bx + F_out = m4 (a_slider - gx); By + N = -m4 gy. Singular where the rod is
    perpendicular to the guide (|cos theta3| <= SINGULAR_TOLERANCE).
    """
    n = state.rows
    matrix = np.zeros((n, 8, 8))
    rhs = np.zeros((n, 8))
    if loads.output_torque != 0:
        raise ValueError("a slider-crank takes output_force (along the guide), not output_torque")
    with np.errstate(all="ignore"):
        acc_b, force_terms, inertia_terms, length = _fill_input_and_coupler(
            matrix, rhs, state, loads, masses, 7)
        gravity = np.asarray(loads.gravity, dtype=float)
        m4 = (masses.output or NO_MASS).mass
        matrix[:, 6, 4] = 1.0                # rod on slider, x
        matrix[:, 7, 5] = 1.0                # rod on slider, y
        matrix[:, 7, 6] = 1.0                # guide's normal force
        rhs[:, 6] = m4 * (acc_b[:, 0] - gravity[0]) - loads.output_force
        rhs[:, 7] = -m4 * gravity[1]
        rod = state.B - state.A
        singular = ~(np.abs(rod[:, 0]) / np.linalg.norm(rod, axis=1) > SINGULAR_TOLERANCE)
        solution = _solve(matrix, rhs, singular)
        force_terms += [abs(loads.output_force), m4 * np.abs(gravity).sum(),
                        m4 * _finite_max(acc_b[:, 0])]
        force_scale, torque_scale = _scales(force_terms, inertia_terms, 0.0, length)
        guide = np.stack([np.where(singular, np.nan, 0.0), solution[:, 6]], axis=1)
        pins = {"A0": solution[:, 0:2], "A": solution[:, 2:4], "B": solution[:, 4:6],
                "guide": guide}
        return LoadRows(solution[:, 7], pins, singular, mechanical_advantage(state),
                        force_scale, torque_scale, ("A0", "A", "B", "guide"))


def mechanical_advantage(state: FourBarState | SliderCrankState) -> np.ndarray:
    """Static mechanical advantage per row, velocity-ratio form, NaN at a toggle (infinite).

    Four-bar: MA = omega_in / omega_out = c sin(theta3 - theta4) / (a sin(theta3 - theta2))
    = ((B - B0) x (B - A)) / ((A - A0) x (B - A)), dimensionless; by virtual work it is the
    torque the output delivers over the input torque (Norton, ch. 6, mechanical advantage).
    Slider-crank: MA = omega_in / v_slider = (B - A)_x / ((A - A0) x (B - A)) in 1/m, the
    force the slider delivers per N m of input torque. Toggle: input and coupler collinear,
    |sin(theta3 - theta2)| <= SINGULAR_TOLERANCE. Signed: positive when the output turns (or
    the slider moves along +x) as the input turns counter-clockwise.
    """
    with np.errstate(all="ignore"):
        crank, coupler = state.A - state.A0, state.B - state.A
        denominator = _cross(crank, coupler)
        toggle = ~(np.abs(denominator) > SINGULAR_TOLERANCE * np.linalg.norm(crank, axis=1)
                   * np.linalg.norm(coupler, axis=1))
        if isinstance(state, FourBarState):
            numerator = _cross(state.B - state.B0, coupler)
        else:
            numerator = coupler[:, 0]
        return np.where(toggle, np.nan, numerator / np.where(toggle, 1.0, denominator))


def _snap(values, scale):
    """Round-off below the noise floor of `scale` -> 0 (linkcli.noise.snap), as an array."""
    return np.asarray(snap(np.asarray(values, dtype=float), float(scale)), dtype=float)


def forces_rows(rows: LoadRows, inputs) -> list[dict]:
    """`forces.rows`: per row input, input_torque, pins {name: {x, y, magnitude}},
    mechanical_advantage; None where the row is singular (forces) or a toggle (MA)."""
    def column(values, scale=None):
        values = values if scale is None else _snap(values, scale)
        return [v if math.isfinite(v) else None for v in np.asarray(values).tolist()]
    torque = column(rows.input_torque, rows.torque_scale)
    advantage = column(rows.mechanical_advantage)
    pins = {name: (column(rows.pins[name][:, 0], rows.force_scale),
                   column(rows.pins[name][:, 1], rows.force_scale),
                   column(rows.magnitude(name), rows.force_scale)) for name in rows.pin_names}
    return [{"input": angle, "input_torque": torque[k],
             "pins": {name: {"x": x[k], "y": y[k], "magnitude": size[k]}
                      for name, (x, y, size) in pins.items()},
             "mechanical_advantage": advantage[k]}
            for k, angle in enumerate(np.asarray(inputs, dtype=float).tolist())]


def _cycle(values, scale) -> dict:
    if values.size == 0:
        return {"max": None, "min": None, "mean": None, "amplitude": None}
    high, low = float(values.max()), float(values.min())
    snapped = _snap([high, low, values.mean(), (high - low) / 2], scale)
    return dict(zip(("max", "min", "mean", "amplitude"), map(float, snapped)))


def load_cycle(rows: LoadRows, inputs) -> dict:
    """The load cycle over the valid (non-singular) rows, for a fatigue check.

    pins: per pin max, min, mean, amplitude (half the range) of the magnitude, and the same
    for x and y; input_torque: peak (the signed torque of largest magnitude; ties within a
    relative linkcli.noise.TIE go to the first row in sweep order), at_input (its input), rms;
    singular_rows: how many rows are dead points (left out; their loads are unbounded).
    """
    inputs = np.asarray(inputs, dtype=float)
    valid = ~rows.singular
    pins = {}
    for name in rows.pin_names:
        xy = rows.pins[name][valid]
        pins[name] = _cycle(np.hypot(xy[:, 0], xy[:, 1]), rows.force_scale)
        pins[name]["x"] = _cycle(xy[:, 0], rows.force_scale)
        pins[name]["y"] = _cycle(xy[:, 1], rows.force_scale)
    torque = rows.input_torque[valid]
    if torque.size:
        first = int(first_max(np.abs(torque)))
        peak, at_input = torque[first], inputs[valid][first]
        rms = np.sqrt(np.mean(torque ** 2))
        summary = {"peak": float(_snap(peak, rows.torque_scale)), "at_input": float(at_input),
                   "rms": float(_snap(rms, rows.torque_scale))}
    else:
        summary = {"peak": None, "at_input": None, "rms": None}
    return {"pins": pins, "input_torque": summary, "singular_rows": int(np.sum(rows.singular))}
