"""The equation of motion integrated in time (scipy.integrate.solve_ivp), with its events.

State y = (q, q', W_drive, W_dampers, W_friction): the drive value, its speed, and the work done
on the linkage by the drive, the dampers and friction since the start (quadratures of their
powers, integrated with the motion so that the energy balance closes on the integrator's own
accuracy). The right-hand side reads the tabulated functions (dynamics.tables) in Python
floats: no array is made per step.

Method (`[dynamics] method`): "auto" is DOP853 (explicit Runge-Kutta of order 8, dense output
of order 7: the best accuracy per evaluation on smooth, non-stiff motion), unless the run is
stiff, where an explicit method's steps are set by stability, not accuracy: at once when its
fastest relaxation rate (`stiffness`: a damper's c g'^2 / M, a motor curve's slope / M) times
its duration exceeds STIFF, or when DOP853 has spent EXPLICIT_SHARE of the budget (friction's
smoothed sign near rest, a shorter stiffness) -- then LSODA (Adams / BDF, switching to the
stiff method by itself). DOP853 runs as dynamics.stepper.SteadyDOP853 (its stage sums free of
the machine's BLAS) and starts every segment from stepper.first_step: with the table's bits
the same on every CPU (dynamics.tables), a run repeats its steps everywhere. LSODA's internal
decisions (its order, its Newton iterations, with the BLAS of the machine) can move a stiff
run's last printed digits from one CPU to another.

Tolerances (RTOL): 1e-11 relative for the Runge-Kutta methods and Radau (where another CPU's
tables differ in their last bit, a run may take another step or two: at 1e-11 that moves its
printed digits a thousand times less than at 1e-10), 1e-12 for LSODA and BDF (their error
estimates run looser), and absolute the same times ABSOLUTE (1e-3) of each state's scale (1
rad; the speed scale; the energy scale): a linkage released from rest moves at speeds far below
its scale at first, and an error made there shifts the whole run in time.

A table law (a damper's valve table, a motor's curve: elements.Law) is smooth only to its first
derivative at its rows: the integration stops at each row its argument crosses (`kink_functions`
as terminal events) and starts again there, so that no step straddles one.

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

RTOL = {"DOP853": 1e-11, "RK45": 1e-11, "Radau": 1e-11, "BDF": 1e-12, "LSODA": 1e-12}
# relative tolerance per method (module docstring); LSODA's and BDF's error estimates run looser
# than the Runge-Kutta methods' (the energy balance over ten damped cycles: 1e-5 of the energies
# at 1e-10, 3e-8 at 1e-12).
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


ABSOLUTE = 1e-3  # the absolute tolerance: rtol times this share of each state's scale
STIFF = 1e5  # auto: LSODA at once when the run's stiffness x its duration exceeds this
EXPLICIT_SHARE = 0.2  # auto: DOP853 may spend this share of the budget before LSODA takes over


def method_for(system, asked: str, t_end: float) -> str:
    """The method to run first (module docstring): `asked`, or for "auto" DOP853 unless the
    run is surely stiff -- its fastest relaxation (`stiffness`) a STIFF-th of its duration or
    less, where an explicit method's steps would be set by stability, not accuracy."""
    if asked != "auto":
        return asked
    return "LSODA" if stiffness(system) * t_end > STIFF else "DOP853"


def stiffness(system) -> float:
    """The largest rate (1/s) at which the speed relaxes, over the drive's range: the
    derivative of q'' with respect to q' from the dampers (their steepest slope times g'^2) and
    the drive's curve (its steepest slope), over the generalized inertia M(q). Friction's
    smoothed sign is as steep only within friction_speed of rest: an explicit run that rests
    there long gives way to LSODA (`integrate`)."""
    from linkcli.analysis.dynamics.tables import nodes
    q = nodes(system.lo, system.hi, 256)
    values, slopes = system.table.many(q)
    rate = np.zeros(len(q))
    for element, k in zip(system.elements, system.coordinate_of):
        if element.role == "damper":
            steepest = element.law.steepest if element.law is not None else element.coefficient
            rate += steepest * (slopes[:, 2 + k] + system.winding[k]) ** 2
    if system.drive.law is not None:
        rate += system.drive.law.steepest
    return float(np.max(rate / values[:, 0]))


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


HELD = 1e-9  # a crossed row's function counts as not yet crossed back within this of 0


def kink_functions(system) -> list:
    """One function per table law (a table damper's, a motor's curve) that is zero at each of
    the law's rows (Law.row_phase of the law's argument): integration restarts there, so that
    no step of the integrator straddles a row, where the law's second derivative jumps."""
    table, out = system.table, []
    for element, k in zip(system.elements, system.coordinate_of):
        if element.role == "damper" and element.law is not None:
            col, winding, phase = 2 + k, system.winding[k], element.law.row_phase
            out.append(lambda t, y, col=col, winding=winding, phase=phase:
                       phase((table.at(float(y[0]))[1][col] + winding) * float(y[1])))
    if system.drive.law is not None:
        phase = system.drive.law.row_phase
        out.append(lambda t, y: phase(float(y[1])))
    return out


def _armed(events: list, bases: int, rhs, t0: float, y0, t_end: float) -> list:
    """The events of a (re)start at (t0, y0): a row function at its row (within HELD) is held on
    the side the motion takes it to (a forward step of 1e-9 of the run's span tells), so that
    the start on a row is no crossing."""
    armed = list(events[:bases])
    probe = None
    for fun in events[bases:]:
        value = fun(t0, y0)
        if abs(value) > HELD:
            armed.append(fun)
            continue
        if probe is None:
            step = 1e-9 * max(t_end - t0, 1e-300)
            probe = np.asarray(y0, dtype=float) + step * np.asarray(rhs(t0, y0), dtype=float)
        ahead = fun(t0, probe)
        side = math.copysign(1.0, ahead - value) if ahead != value else 1.0
        armed.append(_held(fun, side))
    return armed


def _held(fun, side: float):
    """`fun` held on `side` (+1 or -1) while it is within HELD of 0: a restart on a row does not
    find that row again."""
    def held(t, y):
        value = fun(t, y)
        return value if value * side > 0 or abs(value) > HELD else side * HELD
    held.terminal, held.direction = fun.terminal, fun.direction
    return held


class Pieces:
    """The dense outputs of consecutive integrations as one: `sol(times)` and `t`."""

    def __init__(self, pieces: list) -> None:
        self.pieces = pieces
        self.starts = np.array([p.t[0] for p in pieces])
        self.t = np.concatenate([p.t if k == 0 else p.t[1:] for k, p in enumerate(pieces)])

    def sol(self, times):
        times = np.atleast_1d(np.asarray(times, dtype=float))
        which = np.clip(np.searchsorted(self.starts, times, side="right") - 1, 0, len(self.pieces) - 1)
        out = np.empty((len(self.pieces[0].y), len(times)))
        for k in np.unique(which):
            mask = which == k
            out[:, mask] = self.pieces[k].sol(times[mask])
        return out


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
    chosen = method_for(system, method, t_end)
    if method == "auto" and chosen == "DOP853":  # stiff after all (friction at rest): LSODA
        explicit = int(EXPLICIT_SHARE * budget)
        run = integrate(system, q0, w0, t_end, stop=stop, marks=marks, method="DOP853", budget=explicit,
                        dead_points=dead_points, extremes=extremes)
        if run.end != "budget":
            return run
        chosen = "LSODA"
        budget -= explicit
    rhs, count = right_hand_side(system, budget)
    w_scale, e_scale = scales(system, w0)
    rtol = RTOL[chosen]
    atol = ABSOLUTE * rtol * np.array([1.0, w_scale, e_scale, e_scale, e_scale])
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
    bases = len(events)
    for kink in kink_functions(system):
        add(kink, "kink", True)
    y0 = np.array([q0, w0, 0.0, 0.0, 0.0])
    return segments(rhs, count, y0, t_end, chosen, rtol, atol, events, kinds, bases,
                    lambda y: (float(y[0]), float(y[1])))


def segments(rhs, count, y0, t_end: float, chosen: str, rtol: float, atol, events: list, kinds: list,
             bases: int, pick) -> Run:
    """solve_ivp from (0, y0) to t_end with `events` (the first `bases` reported, the rest a
    table law's rows: `kind` "kink", where the run restarts), by `chosen` (DOP853 as
    stepper.SteadyDOP853 from stepper.first_step); each event found is (kind, t, *pick(y)).
    The run ends at its duration or at a terminal event ("stop", "dead-point": the last such
    kind found), or on the budget (rhs raising OutOfBudget) or a failed step."""
    from scipy.integrate import solve_ivp
    stepper = chosen
    if chosen == "DOP853":  # its sums independent of the machine's BLAS (dynamics.stepper)
        from linkcli.analysis.dynamics.stepper import SteadyDOP853 as stepper
        from linkcli.analysis.dynamics.stepper import first_step
    found, pieces = [], []
    t0 = 0.0
    armed = _armed(events, bases, rhs, t0, y0, t_end)
    end = "duration"
    floor = 1e-12 * max(t_end, 1e-300)
    while True:
        try:
            first = {} if stepper is chosen else {"first_step": first_step(rhs, t0, y0, t_end, rtol, atol)}
            solution = solve_ivp(rhs, (t0, t_end), y0, method=stepper, rtol=rtol, atol=atol,
                                 events=armed, dense_output=True, **first)
        except OutOfBudget:
            return Run(None, "budget", 0.0, [], count[0], chosen)
        pieces.append(solution)
        for kind, times, states in zip(kinds[:bases], solution.t_events, solution.y_events):
            found.extend((kind, float(t), *pick(y)) for t, y in zip(times, states) if t > floor)
        if solution.status < 0:
            end = "failed"
            break
        if solution.status == 0:
            break
        t_stop = solution.t[-1]
        if any(len(solution.t_events[k]) and solution.t_events[k][-1] == t_stop and kinds[k] != "kink"
               and events[k].terminal for k in range(bases)):
            last = [e for e in found if _kind(e[0]) in ("stop", "dead-point")]
            end = _kind(last[-1][0]) if last else "duration"
            break
        # a table's row crossed: restart there, so that no step straddles its corner
        t0, y0 = float(t_stop), solution.y[:, -1].copy()
        armed = _armed(events, bases, rhs, t0, y0, t_end)
    found.sort(key=lambda e: (e[1], str(e[0])))
    joined = Pieces(pieces)
    return Run(joined, end, float(joined.t[-1]), found, count[0], chosen)


def _kind(kind) -> str:
    """An event's kind: a name, or (name, drive) for an event of one of several drives."""
    return kind if isinstance(kind, str) else kind[0]
