"""How the searches' cost grows with the number of targets or poses.

Usage (from the repository root):

    python3 benchmarks/scaling.py [--repeats 3] [--vs SRC] [--only NAME ...]

Writes, into a temporary folder, problems whose targets lie (with seeded noise of 0.005) on
the coupler curve, or are the coupler poses, of one known crank-rocker (ground 4, input 1.2,
coupler 3.6, output 2.9, coupler point (1.5, 1.1)): path generation with free timing at 20,
80, 160 and 200 targets (200 is the most free timing allows), with prescribed timing at
1000 targets, and motion generation with free timing at 10 and 100 poses. Each is solved
by `linkcli synth FILE -f json --timing` in a process of its own, `--repeats` times; the
table gives the median CPU seconds of the whole process (user + system, start-up
included), its peak memory, the solve's own seconds (`solver.seconds`), the status and
the objective. With `--vs SRC` (another checkout's `src` folder) the same runs are made
with that source alternately (A B A B ...), and the ratios of the medians are printed:
CPU time, not wall time, so that a shared machine's other jobs weigh less.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

import numpy as np

LINKAGE = dict(ground=4.0, input=1.2, coupler=3.6, output=2.9, coupler_point=(1.5, 1.1), coupler_angle=0.35)
BOUNDS = ("ground = [0.5, 10]\ninput = [0.2, 5]\ncoupler = [0.5, 10]\noutput = [0.5, 10]\n")


def coupler(phi: np.ndarray):
    """Coupler point (complex) and coupler direction (rad) of LINKAGE, open branch."""
    d, a, b, c = (LINKAGE[k] for k in ("ground", "input", "coupler", "output"))
    A = a * np.exp(1j * phi)
    v = A - d
    alpha = np.arccos(np.clip((abs(v) ** 2 + c * c - b * b) / (2 * abs(v) * c), -1, 1))
    B = d + c * np.exp(1j * (np.angle(v) - alpha))
    e = np.exp(1j * np.angle(B - A))
    return A + complex(*LINKAGE["coupler_point"]) * e, np.angle(e)


def points(values) -> str:
    return ", ".join("[" + ", ".join(repr(float(v)) for v in row) + "]" for row in values)


def path_problem(n: int, timing: str, rng) -> str:
    phi = np.linspace(0.1, 0.1 + 1.8 * math.pi, n)
    p, _ = coupler(phi)
    p = p + rng.normal(0, 0.005, n) + 1j * rng.normal(0, 0.005, n)
    target = f"points = [{points(np.stack([p.real, p.imag], 1))}]\n"
    if timing == "free":
        target += 'timing = "free"\n'
    else:
        target += f'timing = "prescribed"\ninput_angles = [{", ".join(repr(math.degrees(v)) for v in phi - 0.1)}]\n'
    extra = "input_offset = [-180, 180]\n" if timing == "prescribed" else ""
    return (f'type = "path-generation"\ntitle = "{n} targets, {timing} timing"\n[target]\n{target}[bounds]\n{BOUNDS}'
            'coupler_point = { x = [-10, 10], y = [-10, 10] }\nground_pivot = { x = [-10, 10], y = [-10, 10] }\n'
            f'ground_angle = [-180, 180]\n{extra}[constraints]\ngrashof = "crank-rocker"\n')


def motion_problem(n: int, rng) -> str:
    phi = np.linspace(0.05, 2 * math.pi - 0.3, n)
    p, angle = coupler(phi)
    poses = np.stack([p.real + rng.normal(0, 0.01, n), p.imag + rng.normal(0, 0.01, n),
                      np.degrees(angle + LINKAGE["coupler_angle"] + rng.normal(0, 0.01, n))], 1)
    return (f'type = "motion-generation"\ntitle = "{n} poses"\n[target]\nposes = [{points(poses)}]\ntiming = "free"\n'
            f'[bounds]\n{BOUNDS}ground_pivot = {{ x = [-6, 6], y = [-6, 6] }}\n'
            '[constraints]\ngrashof = "crank-rocker"\nbranch = "either"\n')


def problems() -> dict[str, str]:
    rng = np.random.default_rng(33)
    out = {f"path_free_{n}": path_problem(n, "free", rng) for n in (20, 80, 160, 200)}
    out["path_prescribed_1000"] = path_problem(1000, "prescribed", rng)
    out.update({f"motion_{n}": motion_problem(n, rng) for n in (10, 100)})
    return out


def run(path: str, src: str | None) -> dict:
    """One `linkcli synth` process: its CPU seconds and peak memory (the OS's accounting of
    the finished child), the report's solve seconds, status and objective."""
    env = dict(os.environ)
    if src:
        env["PYTHONPATH"] = src
    exe = shutil.which("linkcli")
    cmd = ([exe] if exe else [sys.executable, "-m", "linkcli"]) + ["synth", path, "-f", "json", "--timing"]
    with tempfile.TemporaryFile(mode="w+") as out:
        proc = subprocess.Popen(cmd, stdout=out, stderr=subprocess.DEVNULL, text=True, env=env)
        _, _, usage = os.wait4(proc.pid, 0)  # this child's own accounting
        proc.returncode = 0
        out.seek(0)
        rep = json.loads(out.read())
    return dict(cpu=usage.ru_utime + usage.ru_stime, peak_mb=usage.ru_maxrss / 1024, solve=rep["solver"]["seconds"],
                status=rep["status"], objective=rep["error"]["objective"])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--vs", default=None, help="another checkout's src folder, run alternately")
    ap.add_argument("--only", nargs="+", default=None)
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory(prefix="scaling_") as folder:
        for name, text in problems().items():
            if args.only and name not in args.only:
                continue
            path = os.path.join(folder, name + ".toml")
            with open(path, "w", encoding="utf-8") as fh:
                fh.write(text)
            runs = {"A": [], "B": []}
            for _ in range(args.repeats):
                runs["A"].append(run(path, None))
                if args.vs:
                    runs["B"].append(run(path, args.vs))
            row = {"problem": name}
            for side, rs in runs.items():
                if rs:
                    row[side] = {k: statistics.median(r[k] for r in rs) for k in ("cpu", "solve")}
                    row[side].update(peak_mb=max(r["peak_mb"] for r in rs), status=rs[-1]["status"],
                                     objective=rs[-1]["objective"])
            rows.append(row)
            print(json.dumps(row), file=sys.stderr, flush=True)
    head = "| problem | CPU s | solve s | peak MB | status | objective |"
    if args.vs:
        head += " CPU s (vs) | peak MB (vs) | status (vs) | objective (vs) | CPU ratio |"
    print(head + "\n|" + "---|" * (head.count("|") - 1))
    for r in rows:
        a = r["A"]
        line = f"| {r['problem']} | {a['cpu']:.2f} | {a['solve']:.2f} | {a['peak_mb']:.0f} | {a['status']} | {a['objective']:.6g} |"
        if "B" in r:
            b = r["B"]
            line += (f" {b['cpu']:.2f} | {b['peak_mb']:.0f} | {b['status']} | {b['objective']:.6g} | "
                     f"{a['cpu'] / b['cpu']:.2f} |")
        print(line)


if __name__ == "__main__":
    main()
