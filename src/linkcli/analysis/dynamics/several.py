"""The equation of motion of a linkage of several drives (k degrees of freedom, the drive values
q = (q_1 .. q_k) its generalized coordinates: the five-bar's input and input2), from its kinematic
coefficients (mechanisms.protocol.Coefficients of k drives). Lagrange's equations written with
the velocity coefficients (Kane's form; Uicker, Pennock & Shigley, Theory of Machines and
Mechanisms, ch. 16, for one input; Haug, Computer-Aided Kinematics and Dynamics of Mechanical
Systems, ch. 6, for several):

    M(q) q'' + h(q, q') = Q(q, q')

    M_ij = sum_b m_b G_b,i . G_b,j + I_b theta_b,i theta_b,j        (+ flywheel_j on drive j)
    h_i  = sum_b m_b G_b,i . (sum_jl G_b,jl q_j' q_l') + I_b theta_b,i (sum_jl theta_b,jl q_j' q_l')
    Q_i  = -dV/dq_i - sum_e F_e g_e,i + T_i(q_i') + Q_friction,i

G_b,i = dG_b/dq_i (the centre's velocity per unit speed of drive i), G_b,jl its second partials,
theta_b likewise; V gravity's and the constant [loads] forces' potential; F_e each element's
force on its coordinate g_e (a distance or an angle; g_e,i its partials), T_i drive i's torque on
the body it turns (whose angle is its drawn angle plus q_i: rate coefficients delta_ij). The
kinetic energy is q'^T M q' / 2, and h is what its time derivative leaves: with no damping,
friction or drive, kinetic + potential + spring energy is constant. One drive is the case k = 1
of the same equation (dynamics.system tabulates it; here it is evaluated exactly at every step).

The integrator's right-hand side (`rhs`) evaluates the coefficients at the state in Python floats
(the home's `coefficients_at`: no array per step) and solves the k x k system by Gaussian
elimination; with pin friction it solves the Newton-Euler equations of all bodies at the state
instead (dynamics.body_forces: the couples depend on the pin forces), which gives the
accelerations with friction in one solve per pass. The history (several_rows.state) evaluates
everything exactly for all output rows at once (numpy), the pin forces by body_forces.

State y = (q_1..q_k, q_1'..q_k', W_drive, W_dampers, W_friction, a_1..a_m): the works done on the
linkage since the start (their powers integrated with the motion), and each angle coordinate of a
torsional element followed continuously (its rate integrated; the exact angle is the home's,
moved by the whole turns that bring it nearest this one), so that a spring wound past a turn
keeps its whole deflection.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.analysis.dynamics import bodies, body_forces
from linkcli.analysis.dynamics.elements import DriveLaw, compile_elements
from linkcli.analysis.dynamics.several_rows import coordinate_rows, state
from linkcli.analysis.dynamics.system import located_error

TWO_PI = 2.0 * math.pi
INERTIA_RTOL = 1e-12  # the generalized inertia's smallest eigenvalue below this of its largest: singular


class Several:
    """A linkage of k drives with its force elements and drive laws, ready to integrate
    (module docstring). `setups`: the DriveSetups in the order of the drive values."""

    def __init__(self, mech, dyn, case, units, metres: float, path: str | None = None) -> None:
        from linkcli.model import LoadCase
        self.mech, self.dyn, self.units, self.metres, self.path = mech, dyn, units, metres, path
        self.case = case = case or LoadCase()
        graph = self.graph = mech.body_graph(case, metres)
        self.names = tuple(name for name, _ in graph.driven)
        self.k = len(self.names)
        by_name = {s.name: s for s in dyn.drives}
        self.setups = tuple(by_name[name] for name in self.names)
        self.laws = [DriveLaw(s.drive) for s in self.setups]
        self.flywheels = [s.flywheel_inertia for s in self.setups]
        self.locked = tuple(j for j, s in enumerate(self.setups) if s.locked)  # held at their start
        self.free = tuple(j for j in range(self.k) if j not in self.locked)
        self.elements = compile_elements(dyn, graph, metres, units)
        self.coordinates, self.coordinate_of = [], []
        for element in self.elements:
            if element.coordinate not in self.coordinates:
                self.coordinates.append(element.coordinate)
            self.coordinate_of.append(self.coordinates.index(element.coordinate))
        self.angles = [k for k, c in enumerate(self.coordinates) if c.kind == "angle"]
        self.threshold = math.sin(dyn.dead_point)
        self.massive = [(b, graph.masses[b]) for b in graph.bodies if graph.masses.get(b) is not None]
        self.friction = None
        if dyn.friction:
            from linkcli.analysis.dynamics.history import friction_of
            self.friction = friction_of(self)

    def error(self, key: str, expected: str, got: str):
        return located_error(self.dyn, self.path, key, expected, got)

    # ------------------------------------------------------------ the start
    def start(self) -> np.ndarray:
        """The initial state y0 (module docstring), after checking the start assembles away from
        a dead point; each angle coordinate starts in (-pi, pi]."""
        q0 = [s.start[0] for s in self.setups]
        w0 = [s.start[1] for s in self.setups]
        pc = self.mech.coefficients_at(q0, self.metres)
        if not pc.valid or pc.lock < self.threshold:
            u = self.units
            said = ", ".join(f"{n} {u.from_rad(q):.6g}" for n, q in zip(self.names, q0))
            why = ("where the linkage does not assemble" if not pc.valid else
                   f"within dead_point ({u.from_rad(self.dyn.dead_point):g} {u.angle}) of a dead point")
            raise self.error(f"dynamics.{self.names[-1]}.start.angle",
                             "start angles where the linkage assembles, away from its dead points "
                             f"({self.mech.DEAD_POINT})", f"{said} ({u.angle}), {why}")
        m = self.inertia_at(pc)
        free = list(self.free)
        reduced = [[m[i][j] for j in free] for i in free]
        if not _smallest_eigenvalue(reduced) > INERTIA_RTOL * sum(reduced[i][i] for i in range(len(free))):
            name = self.names[min(free, key=lambda j: m[j][j])]  # the drive that turns least mass
            raise self.error(f"dynamics.{name}.start.angle", f"masses that move with every drive ([masses] on "
                             f"the links {name} turns, or its flywheel_inertia)", f"no inertia for {name}")
        angles = []
        for k in self.angles:
            g = self._point_coordinate(pc, self.coordinates[k])[0]
            angles.append(math.remainder(g, TWO_PI) if abs(math.remainder(g, TWO_PI)) < math.pi else math.pi)
        return np.array(q0 + w0 + [0.0, 0.0, 0.0] + angles, dtype=float)

    # ------------------------------------------------------------ floats: the integrator's
    def _first(self, pc, body: str, local):
        """(p, p_j) of a body's point at one state (floats; module docstring of bodies)."""
        if body == bodies.GROUND:
            return (float(local[0]), float(local[1])), [(0.0, 0.0)] * self.k
        (x, dx, _), (th, dth, _) = pc.origin[body], pc.angle[body]
        c, s = math.cos(th), math.sin(th)
        rx, ry = c * local[0] - s * local[1], s * local[0] + c * local[1]
        return (x[0] + rx, x[1] + ry), [(dx[j][0] - dth[j] * ry, dx[j][1] + dth[j] * rx) for j in range(self.k)]

    def _end(self, pc, end):
        if end.point is not None:
            body, local = self.graph.points[end.point]
            return self._first(pc, body, local)
        return self._first(pc, bodies.GROUND, (end.at[0] * self.metres, end.at[1] * self.metres))

    def _point_coordinate(self, pc, c):
        """(g, g_j) of a coordinate at one state: a distance, or an angle (the home's, wrapped)."""
        if c.kind == "distance":
            p1, d1 = self._end(pc, c.first)
            p2, d2 = self._end(pc, c.second)
            dx, dy = p2[0] - p1[0], p2[1] - p1[1]
            length = math.hypot(dx, dy)
            rate = [(dx * (d2[j][0] - d1[j][0]) + dy * (d2[j][1] - d1[j][1])) / length for j in range(self.k)]
            return length, rate
        t2, r2 = self._angle_of(pc, c.second)
        t1, r1 = self._angle_of(pc, c.first)
        return t2 - t1, [a - b for a, b in zip(r2, r1)]

    def _angle_of(self, pc, body):
        if body is None:
            return 0.0, [0.0] * self.k
        theta, first, _ = pc.angle[body]
        return theta, list(first)

    def rhs_function(self, budget: int):
        """f(t, y) of the state (module docstring), counting its calls against `budget`."""
        from linkcli.analysis.dynamics.motion import OutOfBudget
        k, graph, mech, metres = self.k, self.graph, self.mech, self.metres
        gx, gy = (float(v) for v in graph.gravity)
        slots = [self.angles.index(c) if c in self.angles else None for c in range(len(self.coordinates))]
        items = [(c, e.role, e.linear, e.stiffness, e.free, e.preload, e.coefficient,
                  e.law.scalar if e.law is not None else None, e.torque)
                 for c, e in zip(self.coordinate_of, self.elements)]  # Element.force in floats
        bodies_at = [(body, mass, float(mass.center[0]), float(mass.center[1]),
                      mass.inertia if mass.inertia and body not in graph.blocks else 0.0)
                     for body, mass in self.massive]
        forces_at = [(graph.points[name], tuple(float(v) for v in f)) for name, f in graph.forces]
        drive_bodies = [body for _, body in graph.driven]
        free_drives = self.free
        count = [0]
        nan = [math.nan] * (2 * k + 3 + len(self.angles))
        works = 2 * k

        def rhs(t, y):
            count[0] += 1
            if count[0] > budget:
                raise OutOfBudget
            y = y.tolist() if hasattr(y, "tolist") else list(y)
            q, w = y[:k], y[k:2 * k]
            if self.friction is not None:
                return self._rhs_friction(y)
            pc = mech.coefficients_at(q, metres)
            if not pc.valid:
                return nan
            pairs = [(i, j, w[i] * w[j]) for i in range(k) for j in range(k)]
            m = [[0.0] * k for _ in range(k)]
            h = [0.0] * k
            gen = [0.0] * k
            for body, mass, cx, cy, spins in bodies_at:
                (_, dx, ddx), (th, dth, ddth) = pc.origin[body], pc.angle[body]
                c, s = math.cos(th), math.sin(th)
                rx, ry = c * cx - s * cy, s * cx + c * cy
                # G_j = x_j + theta_j perp(R c); sum_ij G_ij w_i w_j = X + Th perp(R c) - om^2 R c
                g1 = [(dx[j][0] - dth[j] * ry, dx[j][1] + dth[j] * rx) for j in range(k)]
                ax = ay = rot = 0.0
                for i, j, ww in pairs:
                    ax += ddx[i][j][0] * ww
                    ay += ddx[i][j][1] * ww
                    rot += ddth[i][j] * ww
                om = 0.0
                for j in range(k):
                    om += dth[j] * w[j]
                om2 = om * om
                ax += -rot * ry - om2 * rx
                ay += rot * rx - om2 * ry
                mm = mass.mass
                for i in range(k):
                    gi = g1[i]
                    row = m[i]
                    for j in range(k):
                        row[j] += mm * (gi[0] * g1[j][0] + gi[1] * g1[j][1])
                    h[i] += mm * (gi[0] * ax + gi[1] * ay)
                    gen[i] += mm * (gx * gi[0] + gy * gi[1])
                if spins:
                    inertia = spins
                    for i in range(k):
                        row = m[i]
                        for j in range(k):
                            row[j] += inertia * dth[i] * dth[j]
                        h[i] += inertia * dth[i] * rot
            for (body, local), (fx, fy) in forces_at:
                _, p1 = self._first(pc, body, local)
                for i in range(k):
                    gen[i] += fx * p1[i][0] + fy * p1[i][1]
            for j, body in enumerate(drive_bodies):
                if self.flywheels[j]:
                    _, dth, ddth = pc.angle[body]
                    h_rot = 0.0
                    for a, b, ww in pairs:
                        h_rot += ddth[a][b] * ww
                    for i in range(k):
                        for l in range(k):
                            m[i][l] += self.flywheels[j] * dth[i] * dth[l]
                        h[i] += self.flywheels[j] * dth[i] * h_rot
            damping = 0.0
            at = []  # per coordinate: (g followed, g_j, rate)
            for coordinate, slot in zip(self.coordinates, slots):
                g, dg = self._point_coordinate(pc, coordinate)
                if slot is not None:
                    tracked = y[works + 3 + slot]
                    g += TWO_PI * round((tracked - g) / TWO_PI)
                rate = 0.0
                for i in range(k):
                    rate += dg[i] * w[i]
                at.append((g, dg, rate))
            for c, role, linear, stiffness, free, preload, coefficient, law, torque in items:
                g, dg, rate = at[c]
                if role == "spring":
                    force = (preload if linear else 0.0) + stiffness * (g - free)
                elif role == "damper":
                    force = law(rate) if law is not None else coefficient * rate
                    damping -= force * rate
                else:
                    force = -torque
                for i in range(k):
                    gen[i] -= force * dg[i]
            rates = [at[c][2] for c in self.angles]
            torques = [law.scalar(w[j]) for j, law in enumerate(self.laws)]
            for j in range(k):
                gen[j] += torques[j]
            qdd = [0.0] * k  # a locked drive's row is its reaction: not solved for
            for j, v in zip(free_drives, _solve([[m[i][l] for l in free_drives] for i in free_drives],
                                                [gen[i] - h[i] for i in free_drives])):
                qdd[j] = v
            power = sum(torques[j] * w[j] for j in range(k))
            return list(w) + qdd + [power, damping, 0.0] + rates

        return rhs, count

    def _rhs_friction(self, y):
        """The right-hand side with pin friction: the Newton-Euler equations of all bodies at the
        state (body_forces.Assembly, the accelerations unknown) solved once for the known loads
        and once per pin for a unit friction couple there; the couples' fixed point
        (tau_p = -mu r_p |F_p| sign~(relative rotation), as body_forces' friction) is then
        iterated on that small linear map in Python floats, as dynamics.friction does for one
        drive."""
        from linkcli.analysis.dynamics.history import element_loads
        k, graph, f = self.k, self.graph, self.friction
        q = np.array([y[:k]])
        w = np.array([y[k:2 * k]])
        pc = self.mech.coefficients_at(y[:k], self.metres)
        if not (pc.valid and pc.lock > 0):
            return [math.nan] * len(y)
        coef = one_row(pc, q)
        tracked = y[2 * k + 3:]
        coords = []
        for c, coordinate in enumerate(self.coordinates):
            g, dg = coordinate_rows(self, coef, coordinate)
            if coordinate.kind == "angle":
                near = tracked[self.angles.index(c)]
                g = g + TWO_PI * np.round((near - g) / TWO_PI)
            coords.append((g, dg))
        rates = [np.sum(dg * w, axis=1) for _, dg in coords]
        per_element, _, loads, _, _ = element_loads(self, coef, coords, rates)
        damping = 0.0
        for element, c, force in zip(self.elements, self.coordinate_of, per_element):
            if element.role == "damper":
                damping -= float(force[0] * rates[c][0])
        torque = [law.scalar(y[k + j]) for j, law in enumerate(self.laws)]
        assembly = body_forces.Assembly(graph, coef, True, self.locked)
        columns = [assembly.rhs(w)]
        assembly.add_loads(columns[0], loads)
        assembly.add_drive(columns[0], np.array([torque]))
        pins = [name for name, *_ in graph.pins]
        for name in pins:
            b = np.zeros_like(columns[0])
            assembly.add_pin_friction(b, name, np.ones(1))
            columns.append(b)
        x = assembly.inverse().solve(np.stack(columns, axis=2))[0]  # (m, 1 + pins)
        if not np.all(np.isfinite(x)):
            return [math.nan] * len(y)
        base, unit = x[:, 0].tolist(), x[:, 1:].T.tolist()
        layout = assembly.layout
        cols = [layout.pin_col[p] for p in pins]
        rel = []  # each pin's relative rotation rate
        for _, _, exerting, acted in graph.pins:
            r = bodies.angle(coef, acted)[1][0] - bodies.angle(coef, exerting)[1][0]
            rel.append(float(np.sum(r * w[0])))
        weights = [-f.mu * f.radii[p] * v / math.sqrt(v * v + f.eps * f.eps) for p, v in zip(pins, rel)]
        amounts = [0.0] * len(pins)
        current = list(base)
        scale = max(abs(v) for v in base) if base else 0.0
        last = math.inf
        for _ in range(body_forces.FRICTION_ITERATIONS):
            new = [wt * math.hypot(current[c], current[c + 1]) for wt, c in zip(weights, cols)]
            current = list(base)
            for amount, column in zip(new, unit):
                for r in range(len(current)):
                    current[r] += column[r] * amount
            change = max([abs(a - b) for a, b in zip(new, amounts)] + [0.0])
            amounts = new
            scale = max([scale] + [abs(v) for v in current])
            floor = max(scale, 1e-300) * max(f.radii.values())
            if change <= body_forces.FRICTION_RTOL * floor or (change <= body_forces.FRICTION_STALL * floor
                                                                and change >= last):
                break
            last = change
        else:
            return [math.nan] * len(y)
        qdd = [0.0 if j in self.locked else current[c] for j, c in enumerate(layout.drive_cols)]
        power = sum(t * v for t, v in zip(torque, y[k:2 * k]))
        lost = sum(a * r for a, r in zip(amounts, rel))
        return list(y[k:2 * k]) + qdd + [power, damping, lost] + [float(rates[c][0]) for c in self.angles]

    # ------------------------------------------------------------ scales
    def inertia_at(self, pc) -> list:
        """M (k x k lists) at one state, in Python floats (module docstring)."""
        k = self.k
        m = [[0.0] * k for _ in range(k)]
        for body, mass in self.massive:
            _, g1 = self._first(pc, body, mass.center)
            spins = mass.inertia if mass.inertia and body not in self.graph.blocks else 0.0
            dth = pc.angle[body][1]
            for i in range(k):
                for j in range(k):
                    m[i][j] += mass.mass * (g1[i][0] * g1[j][0] + g1[i][1] * g1[j][1]) + spins * dth[i] * dth[j]
        for fly, (_, body) in zip(self.flywheels, self.graph.driven):
            dth = pc.angle[body][1]
            for i in range(k):
                for j in range(k):
                    m[i][j] += fly * dth[i] * dth[j]
        return m

    def scales(self, y0) -> tuple[np.ndarray, float]:
        """(speed scale per drive rad/s, energy scale J) of a run: the start's kinetic energy,
        the drives' work over a turn, the springs' energy at the start, gravity's and the
        constant loads' work over the linkage's size, against the smallest generalized inertia
        of the free drives. In Python floats: the tolerances, hence the steps, are the same on
        every CPU."""
        k = self.k
        y0 = [float(v) for v in y0]
        pc = self.mech.coefficients_at(y0[:k], self.metres)
        m = self.inertia_at(pc)
        w = y0[k:2 * k]
        kinetic = 0.5 * sum(w[i] * m[i][j] * w[j] for i in range(k) for j in range(k))
        spring = 0.0
        for element, c in zip(self.elements, self.coordinate_of):
            if element.role == "spring":
                g = self._point_coordinate(pc, self.coordinates[c])[0]
                if c in self.angles:
                    tracked = y0[2 * k + 3 + self.angles.index(c)]
                    g += TWO_PI * round((tracked - g) / TWO_PI)
                spring += float(element.energy(g))
        size = self.mech.size() * self.metres
        g = math.hypot(*self.graph.gravity)
        energy = max(kinetic, spring, sum(law.scale for law in self.laws) * TWO_PI,
                     sum(mass.mass for _, mass in self.massive) * g * size,
                     sum(math.hypot(*f) for _, f in self.graph.forces) * size, 1e-300)
        for element in self.elements:
            if element.role == "couple":
                energy = max(energy, abs(element.torque) * TWO_PI)
        speed = math.sqrt(2.0 * energy / max(_smallest_eigenvalue([[m[i][j] for j in self.free] for i in self.free]),
                                             1e-300))
        return np.maximum(np.abs(np.array(y0[k:2 * k])), speed), energy

    def stiffness(self, y0) -> float:
        """The fastest rate (1/s) at which the speeds relax at the start: the largest eigenvalue
        of M^-1 D, D = sum over dampers of their steepest slope g_e g_e^T plus the motors' curves'
        steepest slopes on the diagonal (dynamics.motion.stiffness for k drives)."""
        k = self.k
        st = state(self, y0[None, :k], y0[None, k:2 * k], y0[None, 2 * k + 3:])
        d = np.zeros((k, k))
        for element, c in zip(self.elements, self.coordinate_of):
            if element.role == "damper":
                slope = element.law.steepest if element.law is not None else element.coefficient
                dg = st.coords[c][1][0]
                d += slope * np.outer(dg, dg)
        for j, law in enumerate(self.laws):
            if law.law is not None:
                d[j, j] += law.law.steepest
        rates = np.linalg.eigvals(np.linalg.solve(st.inertia[0], d))
        return float(np.max(np.abs(rates)))


def _smallest_eigenvalue(m: list) -> float:
    """The smallest eigenvalue of a small symmetric matrix: closed forms for 1 x 1 and 2 x 2 (the
    same digits on every CPU), LAPACK beyond."""
    if len(m) == 1:
        return m[0][0]
    if len(m) == 2:
        mean, half = 0.5 * (m[0][0] + m[1][1]), 0.5 * (m[0][0] - m[1][1])
        return mean - math.hypot(half, 0.5 * (m[0][1] + m[1][0]))
    return float(np.min(np.linalg.eigvalsh(np.array(m))))


def one_row(pc, q):
    """The Coefficients of one row (numpy, drive axes last) from the floats of `coefficients_at`:
    the integrator's friction builds its Newton-Euler equations on them (the numpy path's
    construction costs more than its arithmetic for one row)."""
    from linkcli.mechanisms.protocol import Coefficients
    origin = {b: (np.array([x]), np.array([first]).transpose(0, 2, 1), np.array([second]).transpose(0, 3, 1, 2))
              for b, (x, first, second) in pc.origin.items()}
    angle = {b: (np.array([t]), np.array([first]), np.array([second])) for b, (t, first, second) in pc.angle.items()}
    return Coefficients(q=q, origin=origin, angle=angle, valid=np.array([pc.valid]), lock=np.array([pc.lock]),
                        watched={name: np.array([v]) for name, v in pc.watched.items()})


def _solve(a: list, b: list) -> list:
    """x with a x = b, a small dense system in Python floats (Gaussian elimination with partial
    pivoting: the same digits on every CPU)."""
    n = len(b)
    a = [row[:] + [b[i]] for i, row in enumerate(a)]
    for col in range(n):
        pivot = max(range(col, n), key=lambda r: abs(a[r][col]))
        a[col], a[pivot] = a[pivot], a[col]
        p = a[col][col]
        if p == 0.0:
            return [math.nan] * n
        for r in range(col + 1, n):
            f = a[r][col] / p
            if f:
                for c in range(col, n + 1):
                    a[r][c] -= f * a[col][c]
    x = [0.0] * n
    for r in range(n - 1, -1, -1):
        x[r] = (a[r][n] - sum(a[r][c] * x[c] for c in range(r + 1, n))) / a[r][r]
    return x
