"""The equation of motion integrated in time (scipy.integrate.solve_ivp), with its events.

State y = (q, q', W_drive, W_dampers, W_friction): the drive value, its speed, and the work done
on the linkage by the drive, the dampers and friction since the start (quadratures of their
powers, integrated with the motion so that the energy balance closes on the integrator's own
accuracy). The right-hand side reads the tabulated functions (dynamics.tables) in Python
floats: no array is made per step.

Method (`[dynamics] method`): "auto" is DOP853 (explicit Runge-Kutta of order 8, dense output
of order 7: the best accuracy per evaluation on smooth, non-stiff motion) when nothing damps
the linkage, and LSODA (Adams / BDF, switching to the stiff method by itself) with a damper or
friction, whose time constants (a damper's M / c, friction's smoothed sign at rest) can be far
shorter than the motion's. Tolerances (RTOL): 1e-10 relative for the Runge-Kutta methods and
Radau, 1e-12 for LSODA and BDF, and absolute the same times the scale of each state (1 rad; the
speed scale; the energy scale), so that printed digits settle.

Events (solve_ivp's root finding on the dense output): `stop` (the drive reaches the stop
angle: the run ends), `dead-point` (a closure's transmission angle comes within dead_point of
0 or 180 deg: the run ends, as a one-drive model ends there), `reversal` (the speed changes
sign), `mark` (the drive passes a marked angle). Every evaluation counts against a budget
([solver] budget, default DEFAULT_BUDGET): a run that needs more ends, not converged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

RTOL = {"DOP853": 1e-10, "RK45": 1e-10, "Radau": 1e-10, "BDF": 1e-12, "LSODA": 1e-12}
# relative tolerance per method; the absolute one is the same times each state's scale. LSODA's
# and BDF's error estimates run looser than the Runge-Kutta methods' (measured by the energy
# balance over ten damped cycles: 1e-5 of the energies at 1e-10, 1e-8 at 1e-12), so they are
# asked for two more digits.
DEFAULT_BUDGET = 1_000_000
TWO_PI = 2.0 * math.pi


class OutOfBudget(Exception):
    """The integration needed more evaluations than its budget."""


@dataclass
class Run:
    """An integration: the solve_ivp solution (dense), the end time and why it ended ("stop",
    "dead-point", "duration"), the events [(kind, time, q, q')] in time order (internal q),
    evaluations spent, the method run."""

    solution: object
    end: str
    t_end: float
    events: list = field(default_factory=list)
    evaluations: int = 0
    method: str = ""


def method_for(system, asked: str) -> str:
    if asked != "auto":
        return asked
    damped = any(e.role == "damper" for e in system.elements) or system.dyn.friction > 0
    return "LSODA" if damped else "DOP853"


def right_hand_side(system, budget: int):
    """f(t, y) of the state (module docstring), counting its calls against `budget`."""
    table = system.table
    items = []
    for element, k in zip(system.elements, system.coordinate_of):
        coordinate = system.coordinates[k]
        angle = coordinate.kind == "angle"
        items.append((2 + k, angle, system.winding[k] if angle else 0,
                      TWO_PI * system.turns[k] if angle else 0.0, element.role, element.stiffness,
                      element.free, element.preload, element.coefficient,
                      element.law.scalar if element.law is not None else None, element.torque))
    drive = system.drive.scalar
    friction = getattr(system, "friction_rhs", None)
    count = [0]

    def rhs(t, y):
        count[0] += 1
        if count[0] > budget:
            raise OutOfBudget
        q, w = float(y[0]), float(y[1])
        values, slopes = table.at(q)
        generalized = -slopes[1]
        damping = 0.0
        forces = []
        for col, angle, winding, base, role, k, free, preload, c, law, torque in items:
            g, dg = values[col], slopes[col]
            if angle:
                g = winding * q + g + base
                dg = winding + dg
            if role == "spring":
                force = preload + k * (g - free)
            elif role == "damper":
                v = dg * w
                force = law(v) if law is not None else c * v
                damping -= force * dg * w
            else:
                force = -torque
            generalized -= force * dg
            forces.append(force)
        torque = drive(w)
        generalized += torque
        lost = 0.0
        if friction is not None:
            q_friction = friction(q, w, forces, torque)
            generalized += q_friction
            lost = q_friction * w
        return [w, (generalized - 0.5 * slopes[0] * w * w) / values[0], torque * w, damping, lost]

    return rhs, count


def scales(system, speed: float) -> tuple[float, float]:
    """(speed scale rad/s, energy scale J) of a run: the start's kinetic energy, the range of
    the potential and spring energies over the drive's range, the drive's work over a turn."""
    values = system.node_values
    m_min, m_max = float(np.min(values[:, 0])), float(np.max(values[:, 0]))
    energy = 0.5 * m_max * speed * speed
    energy = max(energy, float(np.ptp(values[:, 1])), system.drive.scale * TWO_PI)
    for element, k in zip(system.elements, system.coordinate_of):
        col = values[:, 2 + k]
        if element.role == "spring":
            g = col + (system.winding[k] * 0.0)
            energy = max(energy, float(np.max(element.energy(g))))
    energy = max(energy, 1e-300)
    return max(abs(speed), math.sqrt(2.0 * energy / m_min)), energy


NEAR_DEAD_POINT = 4.0  # below this many times the threshold, a dead point's lock is evaluated exactly


def dead_point_gap(system, q: float) -> float:
    """lock - sin(dead_point) at q: from the table far from a dead point, from the home's exact
    coefficients near one (the lock varies as a square root there, which no spline follows)."""
    tabulated = system.table.at(q)[0][system.lock_column]
    if tabulated > NEAR_DEAD_POINT * system.threshold:
        return tabulated - system.threshold
    return float(system.exact([q]).lock[0]) - system.threshold


def integrate(system, q0: float, w0: float, t_end: float, *, stop=None, marks=(), method="auto",
              budget: int = DEFAULT_BUDGET, dead_points: bool = True, extremes: bool = False) -> Run:
    """Integrate from (q0, w0) (internal q, rad/s) for at most t_end s; `stop` ends the run at a
    drive value; `marks` are drive values whose crossings are events; `extremes`: the speed's
    extremes (q'' = 0) are events too ("extreme")."""
    from scipy.integrate import solve_ivp
    chosen = method_for(system, method)
    rhs, count = right_hand_side(system, budget)
    w_scale, e_scale = scales(system, w0)
    rtol = RTOL[chosen]
    atol = rtol * np.array([1.0, w_scale, e_scale, e_scale, e_scale])
    events, kinds = [], []

    def add(fun, kind, terminal):
        fun.terminal = terminal
        fun.direction = 0
        events.append(fun)
        kinds.append(kind)

    if stop is not None:
        add(lambda t, y: y[0] - stop, "stop", True)
    add(lambda t, y: y[1], "reversal", False)
    for mark in marks:
        add(lambda t, y, m=mark: y[0] - m, "mark", False)
    if extremes:
        add(lambda t, y: rhs(t, y)[1], "extreme", False)
    if dead_points and (not system.full_turn
                        or float(np.min(system.node_values[:, system.lock_column])) < 2.0 * system.threshold):
        add(lambda t, y: dead_point_gap(system, float(y[0])), "dead-point", True)
    if not system.full_turn:
        add(lambda t, y: y[0] - system.lo, "dead-point", True)
        add(lambda t, y: y[0] - system.hi, "dead-point", True)
    try:
        solution = solve_ivp(rhs, (0.0, t_end), [q0, w0, 0.0, 0.0, 0.0], method=chosen, rtol=rtol,
                             atol=atol, events=events, dense_output=True)
    except OutOfBudget:
        return Run(None, "budget", 0.0, [], count[0], chosen)
    found = []
    floor = 1e-12 * max(t_end, 1e-300)
    for kind, times, states in zip(kinds, solution.t_events, solution.y_events):
        for t, y in zip(times, states):
            if t > floor:
                found.append((kind, float(t), float(y[0]), float(y[1])))
    found.sort(key=lambda e: (e[1], e[0]))
    end = "duration"
    if solution.status == 1:
        last = [e for e in found if e[0] in ("stop", "dead-point")]
        end = last[-1][0] if last else "duration"
    elif solution.status < 0:
        end = "failed"
    return Run(solution, end, float(solution.t[-1]), found, count[0], chosen)
