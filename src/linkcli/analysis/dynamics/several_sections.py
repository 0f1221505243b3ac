"""The report sections of [dynamics] for a linkage of several drives (docs/dynamics.md, "Two
drives"): `simulation`, `history`, `events` and `energy`, as for one drive (dynamics.sections)
with every drive's angle, speed, acceleration and torque keyed by its name. The flywheel and
balancing are one-drive analyses (reading refuses them here).
"""

from __future__ import annotations

import numpy as np

from linkcli.analysis.dynamics.columns import MAX_EVENT_ROWS, column, energy_section, snapped, with_forces
from linkcli.noise import snap


def add_sections(rep: dict, problem, mech, notes: list) -> tuple[str, str] | None:
    """Add simulation, history, events and energy to `rep`; (status, message) when the run falls
    short (a stop not reached: infeasible; over its budget: not-converged), or None."""
    from linkcli.analysis.dynamics import motion, several_motion
    from linkcli.analysis.dynamics.several import Several
    from linkcli.analysis.dynamics.several_rows import state
    from linkcli.analysis.forces import metres_per_unit
    meta = problem.meta
    dyn, units = meta.dynamics, meta.units
    system = Several(mech, dyn, meta.loads, units, metres_per_unit(units), path=meta.path)
    budget = meta.solver.budget or motion.DEFAULT_BUDGET
    run = several_motion.integrate(system, dyn.duration, method=dyn.method, budget=budget)
    if run.end in ("budget", "failed"):
        what = (f"more than {budget} evaluations" if run.end == "budget"
                else "a step below the integrator's round-off")
        rep["simulation"] = {"method": run.method, "end": run.end}
        return ("not-converged", f"the integration did not finish: it needed {what} (raise [solver] "
                "budget, or shorten duration)")
    k = system.k
    times = np.linspace(0.0, run.t_end, dyn.steps)
    y = run.solution.sol(times)
    st = state(system, y[:k].T, y[k:2 * k].T, y[2 * k + 3:].T)
    speed_scale = system.scales(y[:, 0])[0]
    rep["simulation"] = _summary(system, run, y, speed_scale, units)
    rep["history"] = _rows(system, times, y, st, speed_scale, units)
    rep["events"] = _events(system, run, units, notes)
    rep["energy"] = energy_section(st.kinetic, st.potential, st.spring, *(y[2 * k + i, -1] for i in range(3)))
    if not np.all(st.solved.converged):
        notes.append("friction locks the linkage at some rows: their pin forces are null")
    stops = [s for s in system.setups if s.stop is not None]
    if stops and run.end != "stop":
        why = {"dead-point": "a dead point ends the run", "duration": "the run ends at its duration"}[run.end]
        reached = ", ".join(f"{n} {units.from_rad(y[j, -1]):.6g}" for j, n in enumerate(system.names))
        asked = " or ".join(f"{s.name} {units.from_rad(s.stop):.6g}" for s in stops)
        return ("infeasible", f"no drive reaches its stop angle ({asked} {units.angle}): {why} at "
                f"{run.t_end:.6g} s, angles {reached} {units.angle}")
    return None


def _summary(system, run, y, speed_scale, units) -> dict:
    """method, rtol; per drive its start and end angle and speed (and flywheel_inertia); why the
    run ended and when; with a stop, its time and the drive that reached its stop angle."""
    from linkcli.analysis.dynamics.motion import RTOL
    k = system.k
    drives = {}
    for j, (name, setup) in enumerate(zip(system.names, system.setups)):
        drives[name] = {"start_angle": float(units.from_rad(setup.start[0])),
                        "start_speed": float(units.from_rad(setup.start[1])),
                        "end_angle": float(units.from_rad(y[j, -1])),
                        "end_speed": snapped(units.from_rad(y[k + j, -1]), units.from_rad(speed_scale[j]))}
        if setup.flywheel_inertia:
            drives[name]["flywheel_inertia"] = setup.flywheel_inertia
        if setup.locked:
            drives[name]["locked"] = True
    out = {"method": run.method, "rtol": RTOL[run.method], "drives": drives, "end": run.end,
           "end_time": snap(run.t_end, 1.0)}
    if run.end == "stop":
        out["stop_time"] = out["end_time"]
        last = [e for e in run.events if not isinstance(e[0], str) and e[0][0] == "stop"]
        out["stop_drive"] = last[-1][0][1]
    dyn = system.dyn
    if dyn.friction:
        out["friction"] = {"coefficient": dyn.friction,
                           "regularization_speed": float(units.from_rad(dyn.friction_speed))}
    return out


def _rows(system, times, y, st, speed_scale, units) -> list[dict]:
    """`history` rows: time; drives {name: {angle, speed, acceleration, torque}}; pins {x, y,
    magnitude}; elements {name: force}; friction {pin: couple} with friction."""
    k = system.k
    per = {"angle": [column(units.from_rad(y[j]), scale=units.from_rad(1.0)) for j in range(k)],
           "speed": [column(units.from_rad(y[k + j]), scale=units.from_rad(speed_scale[j])) for j in range(k)],
           "acceleration": [column(units.from_rad(st.acceleration[:, j])) for j in range(k)],
           "torque": [column(st.torque[:, j]) for j in range(k)]}
    time = column(times)
    pins_forces = st.solved.pins
    force_scale = max([float(np.nanmax(np.abs(v), initial=0.0)) for v in pins_forces.values()] + [0.0])
    pins = {name: (column(v[:, 0], scale=force_scale), column(v[:, 1], scale=force_scale),
                   column(np.hypot(v[:, 0], v[:, 1]), scale=force_scale)) for name, v in pins_forces.items()}
    elements = {name: column(v) for name, v in st.forces.items()}
    friction = ({name: column(v) for name, v in st.solved.pin_friction.items()}
                if system.dyn.friction else {})
    return [with_forces({"time": time[r], "drives": {name: {key: cols[j][r] for key, cols in per.items()}
                                                     for j, name in enumerate(system.names)}},
                        r, pins, elements, friction)
            for r in range(len(times))]


def _events(system, run, units, notes) -> list[dict]:
    """Every event: its kind, the drive it concerns (stop, reversal, mark), time, drives {name:
    {angle, speed}}."""
    rows, counted = [], 0
    w_scale = max([max(abs(v) for v in e[3]) for e in run.events] + [1e-300])
    for kind, t, q, w in run.events:
        counted += 1
        if len(rows) >= MAX_EVENT_ROWS:
            continue
        name, drive = (kind, None) if isinstance(kind, str) else kind
        row = {"event": name}
        if drive is not None:
            row["drive"] = drive
        row["time"] = float(t)
        row["drives"] = {n: {"angle": float(units.from_rad(a)),
                             "speed": 0.0 if name == "reversal" and n == drive
                             else snapped(units.from_rad(v), units.from_rad(w_scale))}
                         for n, a, v in zip(system.names, q, w)}
        rows.append(row)
    if counted > len(rows):
        notes.append(f"{counted} events; the first {len(rows)} are listed")
    return rows

