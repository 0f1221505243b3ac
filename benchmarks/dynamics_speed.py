"""How long a forward-dynamics run takes (the target: 10 cycles at 1,000 output points a cycle in
1 s or less), and how accurate it is.

Usage (from the repository root):

    python3 benchmarks/dynamics_speed.py [--repeats 5] [--cycles 10] [--points 1000]

Runs problems/crank_rocker_motor.toml's linkage at its running speed (start at 690 deg/s,
no flywheel section) for `--cycles` turns of the crank with `--points` history rows a turn,
four ways: as the example (motor, paddle damper, the rotor's inertia: DOP853), free (no drive,
no damper: its energy conserved), with pin friction too (smoothed within 10 deg/s of rest), and
stiff (without the rotor's inertia the paddle relaxes the light linkage in 1e-4 s: LSODA). Each run builds the equation's
tables, integrates and computes the history (every row's forces) in this process after a
warm-up run (imports paid once): the median CPU seconds (this process's, so that a shared
machine's other jobs weigh less) of `--repeats` runs, part by part, and the energy balance's
largest residual over the history relative to the energies (the integration's own error; for
the free run, the drift of its total energy).
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BASE = (ROOT / "problems" / "crank_rocker_motor.toml").read_text(encoding="utf-8")


def variant(cycles: int, points: int, damper: bool, friction: bool, rotor: bool = True) -> str:
    speed = 690.0
    duration = cycles * 360.0 / speed
    text = BASE.replace("start = { angle = 0, speed = 0 }     # from rest",
                        f"start = {{ angle = 0, speed = {speed} }}")
    text = text.replace("duration = 2\n", f"duration = {duration!r}\n")
    text = text.replace("steps = 201\n", f"steps = {cycles * points}\n")
    text = text.replace("fluctuation = 0.02                   # the flywheel that holds the speed within +-1 %\n", "")
    if not rotor:
        text = text.replace("flywheel_inertia = 3.9", "# flywheel_inertia = 3.9")
    if not damper:
        text = text.replace('paddle = { link = "output", coefficient = 40 }', "")
        text = text.replace("[dampers]\n", "")
        text = text.replace("drive = { torque_speed", "# drive = { torque_speed")
    if friction:
        text = text.replace("[dynamics]\n", "[joints]\nA0 = { diameter = 20 }\nA = { diameter = 12 }\n"
                            "B = { diameter = 12 }\nB0 = { diameter = 20 }\n[dynamics]\nfriction = 0.1\n"
                            "friction_speed = 10\n", 1)
    return text


def one(text: str) -> dict:
    """Seconds of the parts of one run, and its accuracy figures."""
    import numpy as np

    from linkcli import mechanisms
    from linkcli.analysis.dynamics import history, motion
    from linkcli.analysis.dynamics.system import System
    from linkcli.reading.load import load
    problem = load("bench.toml", text.encode())
    meta = problem.meta
    dyn = meta.dynamics
    started = time.process_time()
    system = System(mechanisms.of(problem.linkage), dyn, meta.loads, meta.units,
                    meta.units.mm_per_length / 1000.0)
    built = time.process_time()
    run = motion.integrate(system, dyn.start[0], dyn.start[1], dyn.duration, method=dyn.method)
    integrated = time.process_time()
    times, y, st = history.at_times(system, run, dyn.steps)
    done = time.process_time()
    energy = st.kinetic + (st.potential - st.potential[0]) + st.spring
    works = y[2] + y[3] + y[4]
    scale = max(float(np.max(np.abs(energy))), float(np.max(np.abs(works))), 1e-300)
    residual = float(np.max(np.abs(energy - energy[0] - works))) / scale
    return {"tables": built - started, "integrate": integrated - built, "history": done - integrated,
            "total": done - started, "residual": residual, "method": run.method,
            "evaluations": run.evaluations, "rows": len(times)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--cycles", type=int, default=10)
    parser.add_argument("--points", type=int, default=1000)
    args = parser.parse_args()
    cases = {"the example (motor, paddle)": (True, False, True), "free, no damping": (False, False, True),
             "with pin friction": (True, True, True), "stiff: no rotor (LSODA)": (True, False, False)}
    one(variant(1, 10, True, False))  # warm-up: imports, caches
    print(f"{args.cycles} cycles x {args.points} points a cycle; median CPU s of {args.repeats} runs")
    print(f"{'case':28s} {'method':7s} {'tables':>7s} {'integr.':>8s} {'history':>8s} {'total':>7s} "
          f"{'evals':>7s} {'residual':>9s}")
    for name, (damper, friction, rotor) in cases.items():
        text = variant(args.cycles, args.points, damper, friction, rotor)
        runs = [one(text) for _ in range(args.repeats)]
        med = {k: statistics.median(r[k] for r in runs) for k in ("tables", "integrate", "history", "total")}
        last = runs[-1]
        print(f"{name:28s} {last['method']:7s} {med['tables']:7.3f} {med['integrate']:8.3f} "
              f"{med['history']:8.3f} {med['total']:7.3f} {last['evaluations']:7d} {last['residual']:9.1e}")


if __name__ == "__main__":
    main()
