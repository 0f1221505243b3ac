"""Pin and guide friction in the integrator's right-hand side.

The friction couples depend on the pin forces, and the pin forces on everything that loads the
linkage: the inertia terms (q'^2 and the acceleration), gravity and the constant loads, each
element's force, the drive's torque, and the friction itself (dynamics.body_forces). The
equations being linear, the forces are the combination of fixed responses: the pin and guide
forces per unit of each load (body_forces.responses, the drive's acceleration eliminated),
tabulated over the drive's range at the nodes of the equation's own table (dynamics.tables) with
the pins' relative rotation and the guides' sliding rate coefficients. At each evaluation the
couples are found by fixed-point iteration on that small linear map (FRICTION_RTOL, at most
body_forces.FRICTION_ITERATIONS passes, each evaluation starting from the last one's couples:
the integrator's calls follow one another closely), and their generalized force is

    Q_friction = sum_pins tau_j (theta_acted' - theta_exerting') + sum_guides f_g v_g'

(tau_j = -mu r_j |F_j| sign~(rel. rotation), f_g = -mu |N_g| sign~(sliding): virtual work).
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.analysis.dynamics import bodies, body_forces
from linkcli.analysis.dynamics.tables import SplineTable, nodes

FRICTION_RTOL = 1e-15  # to round-off: the couples are then a smooth function of the state


def unit_loads(system, coef) -> list:
    """[gravity's companions: the constant [loads] forces] + one Loads per element for a unit
    force of it (a tension at its ends, or a restoring torque), at the rows of `coef`."""
    graph = system.graph
    constant = body_forces.Loads(
        [(graph.points[name][0], bodies.point(graph, coef, name)[0], np.asarray(f, dtype=float))
         for name, f in graph.forces], [])
    out = [constant]
    n = len(coef.q)
    for element, k in zip(system.elements, system.coordinate_of):
        c = system.coordinates[k]
        if c.kind == "distance":
            p1 = bodies.end_point(graph, coef, c.first, system.metres)[0]
            p2 = bodies.end_point(graph, coef, c.second, system.metres)[0]
            d = p2 - p1
            u = d / np.hypot(d[:, 0], d[:, 1])[:, None]
            out.append(body_forces.Loads([(_body(graph, c.first), p1, u), (_body(graph, c.second), p2, -u)], []))
        else:
            couples = [(c.second or bodies.GROUND, -np.ones(n))]
            if c.first is not None:
                couples.append((c.first, np.ones(n)))
            out.append(body_forces.Loads([], couples))
    return out


def _body(graph, end) -> str:
    return graph.points[end.point][0] if end.point is not None else bodies.GROUND


class FrictionModel:
    """Q_friction(q, q', element forces, drive torque) for the integrator (module docstring)."""

    def __init__(self, system) -> None:
        from linkcli.analysis.dynamics.history import friction_of
        self.friction = friction_of(system)
        graph = system.graph
        q = nodes(system.lo, system.hi, system.nodes)
        coef = system.mech.coefficients(q, system.metres)
        x, assembly = body_forces.responses(graph, coef, unit_loads(system, coef))
        pin_rate, guide_rate = assembly.rates_at_pins(1.0)
        self.rows, self.columns = x.shape[1], x.shape[2]
        self.pins = [name for name, *_ in graph.pins]
        self.guides = [name for name, *_ in graph.guides]
        self.cols = [assembly.layout.pin_col[p] for p in self.pins]
        self.guide_cols = [assembly.layout.guide_col[g] for g in self.guides]
        rates = np.stack([pin_rate[p] for p in self.pins] + [guide_rate[g] for g in self.guides], axis=1) \
            if self.pins or self.guides else np.zeros((len(q), 0))
        values = np.concatenate([x.reshape(len(q), -1), rates], axis=1)
        self.table = SplineTable(system.lo, system.hi, values, system.full_turn)
        self.loads = 2 + len(system.elements) + 1
        self.radii_list = [self.friction.radii[p] for p in self.pins]
        self.last = []  # the amounts of the last evaluation (the next one starts from them)
        self.lever = max(self.radii_list + [1.0])  # an amount's scale: a force times a radius (m)

    def __call__(self, q: float, w: float, forces: list, torque: float) -> float:
        f = self.friction
        from linkcli.analysis.dynamics.tables import evaluate
        c, u = self.table.coefficients_at(q)
        v = evaluate(c, u)
        size = self.rows * self.columns
        response = v[:size].reshape(self.rows, self.columns)
        loads = np.array([w * w, 1.0] + list(forces) + [torque])
        base = (response[:, :self.loads] @ loads).tolist()
        per_unit = response[:, self.loads:].T.tolist()  # per amount: its column of forces
        rates = v[size:].tolist()
        pins = len(self.pins)
        weights = []  # -mu r sign~ (pins), -mu sign~ (guides): each amount is weight x |force|
        for k, rate in enumerate(rates):
            s_ = rate * w
            eps = f.eps if k < pins else f.eps_v
            weights.append(-f.mu * (self.radii_list[k] if k < pins else 1.0) * s_ / math.sqrt(s_ * s_ + eps * eps))
        scale = 0.0
        for b in base:
            scale = max(scale, abs(b))
        amounts = list(self.last) if len(self.last) == len(rates) else [0.0] * len(rates)
        x = list(base)  # the forces of the last call's amounts: the iteration starts near its end
        for a, column in zip(amounts, per_unit):
            for r in range(len(base)):
                x[r] += column[r] * a
        cols, guide_cols, hypot = self.cols, self.guide_cols, math.hypot
        rows = range(len(base))
        for _ in range(body_forces.FRICTION_ITERATIONS):
            change = 0.0
            for k, j in enumerate(cols):
                a = weights[k] * hypot(x[j], x[j + 1])
                change = max(change, abs(a - amounts[k]))
                amounts[k] = a
            for k, j in enumerate(guide_cols, start=pins):
                a = weights[k] * abs(x[j])
                change = max(change, abs(a - amounts[k]))
                amounts[k] = a
            x = list(base)
            for a, column in zip(amounts, per_unit):
                for r in rows:
                    x[r] += column[r] * a
            for value in x:
                scale = max(scale, abs(value))
            if change <= FRICTION_RTOL * max(scale, 1e-300) * self.lever:
                break
        self.last = amounts
        return sum(a * r for a, r in zip(amounts, rates))


def attach(system) -> None:
    """Give the system its friction model (the integrator reads `system.friction_rhs`)."""
    system.friction_rhs = FrictionModel(system) if system.dyn.friction else None
