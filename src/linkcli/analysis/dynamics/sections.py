"""The report sections of [dynamics] (docs/dynamics.md): `simulation`, `history`, `events`,
`energy` (a run from `start`), `flywheel` (with `fluctuation`) and `balance` (with `balance` or
`counterweights`).

Angles leave in the file's angle unit (the drive's angle followed continuously: two turns are
720 deg), speeds in angle unit/s, times in s, forces in N, torques in N m, energies in J.
Integrated quantities print under the noise floors of analysis.dynamics.columns. A linkage of
several drives has sections of its own (several_sections).
"""

from __future__ import annotations

import numpy as np

from linkcli.analysis.dynamics.columns import MAX_EVENT_ROWS, column, energy_section, snapped, with_forces
from linkcli.noise import snap


def add_sections(rep: dict, problem, mech, notes: list) -> tuple[str, str] | None:
    """Add the asked dynamics sections to `rep`; (status, message) when they fall short of what
    was asked (exit 1: "infeasible", a stop angle not reached or a motor that cannot drive the
    linkage; "not-converged", an integration over its budget), or None."""
    from linkcli.analysis.dynamics.system import System
    from linkcli.analysis.forces import metres_per_unit
    meta = problem.meta
    dyn = meta.dynamics
    if dyn.drives:  # a linkage of several drives: its own equation (dynamics.several)
        from linkcli.analysis.dynamics.several_sections import add_sections as several
        return several(rep, problem, mech, notes)
    units = meta.units
    metres = metres_per_unit(units)
    system = System(mech, dyn, meta.loads, units, metres, path=meta.path)
    shortfall = None
    if dyn.simulates:
        shortfall = _simulation(rep, system, meta, notes)
    if dyn.fluctuation is not None:
        from linkcli.analysis.dynamics.flywheel import section as flywheel_section
        section, short = flywheel_section(system, meta, notes)
        if section is not None:
            rep["flywheel"] = section
        shortfall = shortfall or short
    if dyn.balance:
        from linkcli.analysis.dynamics.balance import section as balance_section
        rep["balance"] = balance_section(system, problem, meta, notes)
    return shortfall


def _simulation(rep, system, meta, notes) -> tuple[str, str] | None:
    from linkcli.analysis.dynamics import history, motion
    dyn = meta.dynamics
    units = meta.units
    q0 = system.internal(dyn.start[0])
    w0 = dyn.start[1]
    stop = None if dyn.stop is None else system.internal(dyn.stop)
    if stop is not None and not system.full_turn and not system.lo <= stop <= system.hi:
        raise system.error("stop.angle", "a stop angle within the drive's range of motion "
                           f"[{units.from_rad(system.external(system.lo)):.6g}, "
                           f"{units.from_rad(system.external(system.hi)):.6g}] ({units.angle}) away from "
                           "its dead points", f"{units.from_rad(dyn.stop):.6g}")
    budget = meta.solver.budget or motion.DEFAULT_BUDGET
    run = motion.integrate(system, q0, w0, dyn.duration, stop=stop,
                           marks=[system.internal(m) for m in dyn.marks], method=dyn.method,
                           budget=budget)
    if run.end in ("budget", "failed"):
        what = (f"more than {budget} evaluations" if run.end == "budget"
                else "a step below the integrator's round-off")
        rep["simulation"] = {"method": run.method, "end": run.end}
        return ("not-converged", f"the integration did not finish: it needed {what} (raise [solver] "
                "budget, or shorten duration)")
    times, y, st = history.at_times(system, run, dyn.steps)
    rep["simulation"] = _summary(system, run, y, dyn, units)
    rep["history"] = _rows(system, times, y, st, units)
    rep["events"] = _events(system, run, units, notes)
    rep["energy"] = _energy(system, y, st)
    if not np.all(st.solved.converged):
        notes.append("friction locks the linkage at some rows: their pin forces are null")
    if stop is not None and run.end != "stop":
        why = {"dead-point": "a dead point ends the run", "duration": "the run ends at its duration"}[run.end]
        return ("infeasible", f"the drive does not reach the stop angle {units.from_rad(dyn.stop):.6g} "
                f"{units.angle}: {why} at {run.t_end:.6g} s, angle "
                f"{units.from_rad(system.external(y[0, -1])):.6g} {units.angle}")
    return None


def _summary(system, run, y, dyn, units) -> dict:
    w_scale, _ = _scales(system, y)
    from linkcli.analysis.dynamics.motion import RTOL
    out = {"method": run.method, "rtol": RTOL[run.method],
           "start": {"angle": float(units.from_rad(dyn.start[0])), "speed": float(units.from_rad(dyn.start[1]))},
           "end": run.end, "end_time": snap(run.t_end, 1.0),
           "end_angle": float(units.from_rad(system.external(y[0, -1]))),
           "end_speed": snapped(units.from_rad(y[1, -1]), units.from_rad(w_scale))}
    if run.end == "stop":
        out["stop_time"] = out["end_time"]
        out["stop_speed"] = out["end_speed"]
    if dyn.friction:
        out["friction"] = {"coefficient": dyn.friction,
                           "regularization_speed": float(units.from_rad(dyn.friction_speed))}
    if dyn.flywheel_inertia:
        out["flywheel_inertia"] = dyn.flywheel_inertia
    return out


def _scales(system, y):
    from linkcli.analysis.dynamics.motion import scales
    return scales(system, float(np.max(np.abs(y[1]))) if y.size else 0.0)


def _rows(system, times, y, st, units) -> list[dict]:
    """`history` rows: time, angle, speed, acceleration, drive_torque, pins {x, y, magnitude},
    elements {name: force}, guides' normal forces with the pins."""
    w_scale, _ = _scales(system, y)
    angle = units.from_rad(system.external(y[0]))
    cols = {"time": column(times), "angle": column(angle, scale=units.from_rad(1.0)),
            "speed": column(units.from_rad(y[1]), scale=units.from_rad(w_scale)),
            "acceleration": column(units.from_rad(st.acceleration)),
            "drive_torque": column(st.torque)}
    solved = st.solved
    forces = {**solved.pins, **solved.guides}
    force_scale = max([float(np.nanmax(np.abs(v), initial=0.0)) for v in forces.values()] + [0.0])
    pins = {name: (column(v[:, 0], scale=force_scale), column(v[:, 1], scale=force_scale),
                   column(np.hypot(v[:, 0], v[:, 1]), scale=force_scale)) for name, v in forces.items()}
    elements = {name: column(v) for name, v in st.forces.items()}
    friction = ({name: column(v) for name, v in solved.pin_friction.items()}
                if system.dyn.friction else {})
    return [with_forces({key: values[k] for key, values in cols.items()}, k, pins, elements, friction)
            for k in range(len(times))]


def _events(system, run, units, notes) -> list[dict]:
    rows = []
    counted = 0
    w_scale = max([abs(e[3]) for e in run.events] + [1e-300])
    for kind, t, q, w in run.events:
        counted += 1
        if len(rows) >= MAX_EVENT_ROWS:
            continue
        rows.append({"event": kind, "time": float(t), "angle": float(units.from_rad(system.external(q))),
                     "speed": 0.0 if kind == "reversal" else snapped(units.from_rad(w), units.from_rad(w_scale))})
    if counted > len(rows):
        notes.append(f"{counted} events; the first {len(rows)} are listed")
    return rows


def _energy(system, y, st) -> dict:
    return energy_section(st.kinetic, st.potential, st.spring, y[2, -1], y[3, -1], y[4, -1])
