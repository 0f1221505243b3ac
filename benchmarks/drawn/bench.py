"""Speed of drawn linkages (docs/drawn.md, "Speed"): the plan over many rows, and one six-bar
analysis with loads against the four-bar's, in process.

    python benchmarks/drawn/bench.py            # linkcli only
    python benchmarks/drawn/bench.py --peers    # also pylinkage (if importable), the same six-bar

Times are the best of REPEATS runs (time.perf_counter), on whatever the machine is doing:
state the machine's load with the figures. The whole-process comparison (start-up included),
CPU time of interleaved runs:

    python3 benchmarks/compare_commands.py --runs 7 -- \
        'linkcli synth benchmarks/drawn/four_bar_3600.toml --format json' \
        'linkcli synth benchmarks/drawn/six_bar_3600.toml --format json'
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
REPEATS = 7


def best(fn, repeats: int = REPEATS) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)


def plan_rows():
    """Seconds for positions, velocities and accelerations of every joint at 10,000 rows."""
    from linkcli import mechanisms
    from linkcli.reading.load import load
    out = {}
    for name in ("drawn_watt", "drawn_stephenson", "drawn_jansen", "drawn_shaper"):
        home = mechanisms.of(load(str(ROOT / "problems" / f"{name}.toml")).linkage)
        kin = home.solved.kin  # the plan and, for a group, its continuation: built once
        q = np.linspace(0.0, 2 * math.pi, 10_000, endpoint=False)
        kin.run(q[:10])
        out[name] = best(lambda: kin.run(q, rates=True))
    return out


def watt_3600():
    """Seconds for the Watt six-bar over 3600 rows: positions only, and with rates."""
    from linkcli import mechanisms
    from linkcli.reading.load import load
    kin = mechanisms.of(load(str(ROOT / "problems" / "drawn_watt.toml")).linkage).solved.kin
    q = np.arange(3600) * (2 * math.pi / 3600)
    return {"positions": best(lambda: kin.run(q, rates=False)), "with rates": best(lambda: kin.run(q, rates=True)),
            "D": kin.run(q[:4], rates=False).pos["D"]}


def analysis():
    """Seconds for load -> solve -> report of the six-bar (3600 steps, loads) and the four-bar."""
    from linkcli.mechanisms.drawn.solved import solved
    from linkcli.pipeline import analyse, solve
    from linkcli.reading.load import load
    out = {}
    for name in ("six_bar_3600", "four_bar_3600"):
        path = str(ROOT / "benchmarks" / "drawn" / f"{name}.toml")

        def once():
            solved.cache_clear()  # a fresh file each time: plan, reach and report
            problem = load(path)
            analyse(problem, solve(problem))
        once()
        out[name] = best(once)
    return out


def pylinkage_six_bar():
    """The same Watt six-bar in pylinkage (positions over 3600 steps, then with kinematics)."""
    import pylinkage as pl
    o2, o4, o6 = pl.Ground(0, 0, name="O2"), pl.Ground(50, 0, name="O4"), pl.Ground(100, 40, name="O6")
    crank = pl.Crank(o2, 20.0, angular_velocity=2 * math.pi / 3600, initial_angle=math.radians(60), name="A")
    b = pl.RRRDyad(crank, o4, 55.0, 40.0, x=60.746240, y=38.529447, name="B")
    c = pl.FixedDyad(o4, b, 25.0, -math.pi / 2, name="C") if hasattr(pl, "FixedDyad") else None
    d = pl.RRRDyad(c, o6, 40.0, 30.0, x=70.792923, y=33.148236, name="D")
    linkage = pl.Linkage([o2, o4, o6, crank, b, c, d], name="Watt")
    out = {}
    start = time.perf_counter()
    first = linkage.step_fast(iterations=4)
    out["first call (compiles)"] = time.perf_counter() - start
    out["D"] = first[:, -1]
    out["positions, step_fast"] = best(lambda: linkage.step_fast(iterations=3600), 3)
    try:
        linkage.set_input_velocity(crank, omega=1.0)
        linkage.step_fast_with_kinematics(iterations=10)
        out["with kinematics"] = best(lambda: linkage.step_fast_with_kinematics(iterations=3600), 3)
    except Exception as exc:  # noqa: BLE001 - report what the peer says
        out["with kinematics"] = f"not run: {exc}"
    out["version"] = pl.__version__
    return out


def main() -> None:
    for name, seconds in plan_rows().items():
        print(f"plan over 10,000 rows (positions, velocities, accelerations): {name}: {seconds * 1e3:.1f} ms")
    watt = watt_3600()
    print(f"Watt six-bar, 3600 rows: positions {watt['positions'] * 1e3:.1f} ms, with velocities and "
          f"accelerations {watt['with rates'] * 1e3:.1f} ms; D at the first rows {watt['D'].tolist()}")
    for name, seconds in analysis().items():
        print(f"analysis in process: {name}: {seconds * 1e3:.1f} ms")
    if "--peers" in sys.argv:
        for key, value in pylinkage_six_bar().items():
            shown = value if isinstance(value, str) else (value.tolist() if isinstance(value, np.ndarray)
                                                          else f"{value * 1e3:.1f} ms")
            print(f"pylinkage {key}: {shown}")


if __name__ == "__main__":
    main()
