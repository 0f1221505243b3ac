"""Time 200-file sweeps three ways: serial, `--jobs 2` and `--cluster local:2`.

Two sweeps, each of 200 problem files written into a temporary folder with its own data
from a seeded generator:
- `closed-form`: 100 `linkage` motion studies and 100 `precision-position` fire-door
  variants (a few milliseconds of work per file);
- `flipper`: a parametric study of a tipping platform's cylinder (flipper-cylinder:
  the base pivot's height and the mass vary; a search, about 0.1 s per file).
Each runs `linkcli synth FILES --format json` in each mode, interleaved, `--repeats`
times; the script checks that the three outputs are the same bytes and prints a markdown
table of wall-clock times (the whole command: start-up, the cluster's start and close).

Usage (from the repository root): python3 benchmarks/cluster_sweep.py [--repeats N] [--sweep NAME]
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
MODES = {"serial": [], "--jobs 2": ["--jobs", "2"], "--cluster local:2": ["--cluster", "local:2"]}


FLIPPER = """type = "flipper-cylinder"
title = "sweep {index}: base pivot at y = {height:.1f} mm, {mass:.0f} kg"
[load]
mass = {mass:.1f}
center_of_mass = [830, 500]
gravity = 9.8
[motion]
start = 0
end = 90
[bounds]
rod_pivot  = {{ x = [0, 350], y = [320, 1380] }}
base_pivot = {{ x = [400, 1400], y = {height:.1f} }}
[cylinder]
bore = 80
rod = 45
dead_length = 300
max_force = 40000
[objective]
minimize = "peak-force"
"""


def write_flipper_sweep(folder: Path, count: int = 200, seed: int = 20) -> list[str]:
    """`count` flipper-cylinder files: base pivot height 0..150 mm, mass 1800..2200 kg."""
    rng = np.random.default_rng(seed)
    files = []
    for index in range(count):
        path = folder / f"flipper{index:03d}.toml"
        path.write_text(FLIPPER.format(index=index, height=rng.uniform(0.0, 150.0),
                                       mass=rng.uniform(1800.0, 2200.0)))
        files.append(str(path))
    return files


def write_sweep(folder: Path, count: int = 200, seed: int = 20) -> list[str]:
    """`count` problem files: even ones a linkage near the fire-door closer (motion and
    kinematics over 72 steps), odd ones its precision positions moved by up to 3 deg."""
    rng = np.random.default_rng(seed)
    files = []
    for index in range(count):
        path = folder / f"sweep{index:03d}.toml"
        if index % 2 == 0:
            ground, crank, coupler, output = np.array([50.0, 27.6, 57.2, 41.1]) * rng.uniform(0.9, 1.1, 4)
            path.write_text(
                f'type = "linkage"\ntitle = "sweep {index}"\n[linkage]\nground = {ground:.4f}\n'
                f'input = {crank:.4f}\ncoupler = {coupler:.4f}\noutput = {output:.4f}\n'
                f'branch = "open"\n[motion]\ninput_speed = 20\nsteps = 72\n[report]\n'
                f'sections = ["lengths", "grashof", "transmission", "motion", "kinematics"]\n')
        else:
            inputs = np.array([45.0, 90.0, 135.0]) + rng.uniform(-3, 3, 3)
            outputs = np.array([52.0, 82.0, 112.0]) + rng.uniform(-3, 3, 3)
            path.write_text(
                f'type = "precision-position"\ntitle = "sweep {index}"\n[linkage]\nground = 50.0\n'
                f'[positions]\ninput = [{", ".join(f"{x:.3f}" for x in inputs)}]\n'
                f'output = [{", ".join(f"{x:.3f}" for x in outputs)}]\n')
        files.append(str(path))
    return files


def run(files: list[str], options: list[str]) -> tuple[float, bytes, int]:
    """(seconds, stdout, exit code) of one `linkcli synth` over the files."""
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "linkcli", "synth", *files, "--format", "json",
                           *options], cwd=ROOT, env=env, capture_output=True)
    return time.perf_counter() - start, done.stdout, done.returncode


SWEEPS = {"closed-form": write_sweep, "flipper": write_flipper_sweep}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--sweep", choices=[*SWEEPS, "all"], default="all")
    args = parser.parse_args()
    names = list(SWEEPS) if args.sweep == "all" else [args.sweep]
    worst = 0
    for name in names:
        worst = max(worst, time_sweep(name, args.repeats))
    sys.exit(worst)


def time_sweep(name: str, repeats: int) -> int:
    """Run one sweep in the three modes; print its table; 1 if the outputs differ."""
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as folder:
        files = SWEEPS[name](Path(folder))
        seconds = {mode: [] for mode in MODES}
        outputs = {}
        for _ in range(repeats):
            for mode, options in MODES.items():
                elapsed, out, code = run(files, options)
                seconds[mode].append(elapsed)
                outputs.setdefault(mode, (out, code))
                assert (out, code) == outputs[mode], f"{mode}: output changed between runs"
    same = len({outputs[mode] for mode in MODES}) == 1
    print(f"\n{name} sweep, {len(files)} files; {platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}; exit code {outputs['serial'][1]}; "
          f"outputs {'byte-identical' if same else 'DIFFER'} across the three modes; "
          f"load average {load_before:.1f} before, {os.getloadavg()[0]:.1f} after\n")
    serial = statistics.median(seconds["serial"])
    print(f"| run | wall time, median of {repeats} (s) | min .. max (s) | vs serial |")
    print("|---|---|---|---|")
    for mode in MODES:
        median = statistics.median(seconds[mode])
        print(f"| `{mode}` | {median:.2f} | {min(seconds[mode]):.2f} .. {max(seconds[mode]):.2f} "
              f"| {serial / median:.2f}x |")
    return 0 if same else 1


if __name__ == "__main__":
    main()
