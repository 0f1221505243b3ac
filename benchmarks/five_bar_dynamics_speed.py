"""How long ten seconds of a five-bar's motion take to simulate (two drives: the equation of
motion evaluated exactly at every step, no tables), and how accurate they are.

Usage (from the repository root):

    python3 benchmarks/five_bar_dynamics_speed.py [--repeats 3] [--seconds 10] [--rows 10000]

Three runs of `--seconds` simulated seconds with `--rows` history rows, each after a warm-up run
(imports paid once), median CPU seconds of this process over `--repeats`, part by part
(integration, history with every pin's force), with the evaluations of the right-hand side and
the energy balance's largest residual over the history relative to the energies:

    free      both drives free, gravity and four springs (tests/analysis/test_five_bar_dynamics.py's
              energy case): the energy is conserved, the residual is its drift
    motors    both cranks on steep motor curves turning together at about 360 deg/s (A and B
              move alike: no dead point), a 0.3 kg coupler under gravity, a viscous hub
    friction  `motors` with pin friction 0.1 in all five pins (the Newton-Euler equations with
              friction's fixed point solved at every evaluation)
"""

from __future__ import annotations

import argparse
import statistics
import time

LINKAGE = """type = "linkage"
[linkage]
mechanism = "five-bar"
ground = 50
input = 40
input2 = 40
coupler = 60
coupler2 = 60
[motion]
inputs = [[120, 60], [115, 65]]
[masses]
input = { mass = 0.05, center = [20.0, 2.0], inertia = 1.2e-5 }
input2 = { mass = 0.06, center = [18.0, -1.5], inertia = 1.5e-5 }
coupler = { mass = 0.30, center = [50.0, 4.0], inertia = 6e-5 }
coupler2 = { mass = 0.08, center = [30.0, -2.0], inertia = 3e-5 }
[loads]
gravity = [0, -9.81]
"""
FREE = """[springs]
left = { link = "input", stiffness = 0.6, free_angle = 120 }
right = { link = "input2", stiffness = 0.5, free_angle = 60 }
pull = { between = ["P", [0, 140]], stiffness = 0.02, free_length = 30, preload = 0.3 }
twist = { links = ["coupler", "coupler2"], stiffness = 0.05, free_angle = -70 }
[dynamics]
duration = SECONDS
steps = ROWS
[dynamics.input]
start = { angle = 128, speed = 40 }
[dynamics.input2]
start = { angle = 55, speed = -60 }
"""
MOTORS = """[dampers]
hub = { link = "input2", coefficient = 0.001 }
[dynamics]
duration = SECONDS
steps = ROWS
FRICTION
[dynamics.input]
drive = { torque_speed = [[0, 2.0], [360, 0.2], [400, -2]] }
start = { angle = 120, speed = 360 }
[dynamics.input2]
drive = { torque_speed = [[0, 2.0], [360, 0.2], [400, -2]] }
start = { angle = 120, speed = 360 }
"""
JOINTS = """[joints]
A0 = { diameter = 6 }
A = { diameter = 4 }
P = { diameter = 4 }
B = { diameter = 4 }
B0 = { diameter = 6 }
"""


def text(case: str, seconds: float, rows: int) -> str:
    body = FREE if case == "free" else MOTORS
    body = body.replace("SECONDS", repr(seconds)).replace("ROWS", str(rows))
    body = body.replace("FRICTION", "friction = 0.1\nfriction_speed = 1" if case == "friction" else "")
    return LINKAGE + (JOINTS if case == "friction" else "") + body


def one(source: str) -> dict:
    import numpy as np

    from linkcli import mechanisms
    from linkcli.analysis.dynamics import several_motion
    from linkcli.analysis.dynamics.several import Several
    from linkcli.analysis.dynamics.several_rows import state
    from linkcli.reading.load import load
    problem = load("bench.toml", source.encode())
    meta = problem.meta
    dyn = meta.dynamics
    started = time.process_time()
    system = Several(mechanisms.of(problem.linkage), dyn, meta.loads, meta.units, meta.units.mm_per_length / 1000.0)
    run = several_motion.integrate(system, dyn.duration, method=dyn.method)
    integrated = time.process_time()
    k = system.k
    times = np.linspace(0.0, run.t_end, dyn.steps)
    y = run.solution.sol(times)
    st = state(system, y[:k].T, y[k:2 * k].T, y[2 * k + 3:].T)
    done = time.process_time()
    energy = st.kinetic + (st.potential - st.potential[0]) + st.spring
    works = y[2 * k] + y[2 * k + 1] + y[2 * k + 2]
    scale = max(float(np.max(np.abs(energy))), float(np.max(np.abs(works))), 1e-300)
    return {"integrate": integrated - started, "history": done - integrated, "total": done - started,
            "residual": float(np.max(np.abs(energy - energy[0] - works))) / scale, "end": run.end,
            "t_end": run.t_end, "method": run.method, "evaluations": run.evaluations, "rows": len(times)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--rows", type=int, default=10_000)
    args = parser.parse_args()
    for case in ("free", "motors", "friction"):
        source = text(case, args.seconds, args.rows)
        one(text(case, 0.05, 11))  # warm-up
        runs = [one(source) for _ in range(args.repeats)]
        last = runs[-1]
        med = {key: statistics.median(r[key] for r in runs) for key in ("integrate", "history", "total")}
        print(f"{case:9s} {last['method']:6s} end {last['end']} at {last['t_end']:.4g} s, "
              f"{last['evaluations']} evaluations, {last['rows']} rows: integrate {med['integrate']:.2f} s, "
              f"history {med['history']:.2f} s, total {med['total']:.2f} s CPU; energy residual "
              f"{last['residual']:.1e}")


if __name__ == "__main__":
    main()
