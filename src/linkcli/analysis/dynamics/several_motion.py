"""The equation of motion of a linkage of several drives (dynamics.several) integrated in time:
the one-drive integrator's settings, methods, tolerances and segments (dynamics.motion), with
the events of k drives.

State y = (q_1..q_k, q_1'..q_k', W_drive, W_dampers, W_friction, followed angles). Method "auto":
DOP853 (motion.SteadyDOP853, its sums free of the machine's BLAS) unless the run is stiff -- its
fastest relaxation at the start (`Several.stiffness`: the dampers' and motor curves' slopes
through M^-1) times its duration above STIFF, or DOP853 spending motion.EXPLICIT_SHARE of the
budget -- then LSODA. STIFF is ten times lower than one drive's: an evaluation here costs tens
of microseconds (about 0.75 ms with friction), not a few, and DOP853's steps on a stiff run are
set by stability at about two evaluations per unit of stiffness x duration. Tolerances motion.RTOL; absolute, rtol x motion.ABSOLUTE of each
state's scale (1 rad; each drive's speed scale; the energies' scale; 1 rad).

Events (solve_ivp's root finding on the dense output):

    stop        a drive reaches its stop angle: the run ends      (kind ("stop", drive))
    dead-point  a closure's transmission angle (the home's `lock`, |sin|) comes within
                dead_point of 0 or 180 deg, or the linkage stops assembling: the run ends --
                past it the linkage does not assemble, or takes the other branch
    reversal    a drive's speed changes sign                      (("reversal", drive))
    mark        a drive passes one of its marked angles           (("mark", drive))

A table law (a damper's table, a motor's curve) restarts the integration at each row its
argument crosses, as for one drive (motion.segments).
"""

from __future__ import annotations

import numpy as np

from linkcli.analysis.dynamics import motion

STIFF = 1e4  # auto: LSODA at once beyond this stiffness x duration (one drive: motion.STIFF, 1e5)


def integrate(system, t_end: float, *, method: str = "auto", budget: int = motion.DEFAULT_BUDGET) -> motion.Run:
    """Integrate from the start of every drive for at most t_end s (module docstring); the
    events are (kind, t, q (k,), q' (k,))."""
    y0 = system.start()
    chosen = method
    if method == "auto":
        chosen = "LSODA" if system.stiffness(y0) * t_end > STIFF else "DOP853"
        if chosen == "DOP853":
            explicit = int(motion.EXPLICIT_SHARE * budget)
            run = integrate(system, t_end, method="DOP853", budget=explicit)
            if run.end != "budget":
                return run
            chosen, budget = "LSODA", budget - explicit
    rhs, count = system.rhs_function(budget)
    k = system.k
    speeds, energy = system.scales(y0)
    rtol = motion.RTOL[chosen]
    scale = np.concatenate([np.ones(k), speeds, [energy] * 3, np.ones(len(system.angles))])
    atol = motion.ABSOLUTE * rtol * scale
    events, kinds = [], []

    def add(fun, kind, terminal):
        fun.terminal = terminal
        fun.direction = 0
        events.append(fun)
        kinds.append(kind)

    for j, (name, setup) in enumerate(zip(system.names, system.setups)):
        if setup.stop is not None:
            add(lambda t, y, j=j, s=setup.stop: y[j] - s, ("stop", name), True)
    for j, name in enumerate(system.names):
        if j in system.free:  # a locked drive's speed stays 0
            add(lambda t, y, j=j: y[k + j], ("reversal", name), False)
    for j, (name, setup) in enumerate(zip(system.names, system.setups)):
        for mark in setup.marks:
            add(lambda t, y, j=j, m=mark: y[j] - m, ("mark", name), False)
    mech, metres, threshold = system.mech, system.metres, system.threshold

    def dead_point(t, y):
        pc = mech.coefficients_at(y[:k].tolist(), metres)
        return (pc.lock if pc.valid else 0.0) - threshold

    add(dead_point, "dead-point", True)
    bases = len(events)
    for kink in kink_functions(system):
        add(kink, "kink", True)
    return motion.segments(rhs, count, y0, t_end, chosen, rtol, atol, events, kinds, bases,
                           lambda y: (tuple(float(v) for v in y[:k]), tuple(float(v) for v in y[k:2 * k])))


def kink_functions(system) -> list:
    """One function per table law that is zero at each of its rows (motion.kink_functions for k
    drives): a damper table's rows in its coordinate's rate, a motor curve's in its drive's
    speed."""
    k, out = system.k, []
    for element, c in zip(system.elements, system.coordinate_of):
        if element.role == "damper" and element.law is not None:
            coordinate, phase = system.coordinates[c], element.law.row_phase

            def fun(t, y, coordinate=coordinate, phase=phase):
                pc = system.mech.coefficients_at(y[:k].tolist(), system.metres)
                if not pc.valid:
                    return 1.0
                _, dg = system._point_coordinate(pc, coordinate)
                return phase(sum(dg[i] * float(y[k + i]) for i in range(k)))
            out.append(fun)
    for j, law in enumerate(system.laws):
        if law.law is not None:
            out.append(lambda t, y, j=j, phase=law.law.row_phase: phase(float(y[k + j])))
    return out
