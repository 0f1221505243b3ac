"""Write the timing-free bench targets of the coupler-curve atlas (problems/bench/free_*.toml
and their shipped copies in src/linkcli/bench_problems/).

Usage (from the repository root):

    python3 benchmarks/atlas_targets.py

Each file's targets are computed here (10 decimals) from a known four-bar, recorded in the
file, by the conventions of docs/format.md in complex numbers (A = a e^{i phi}, psi =
arg(A - B0) -/+ alpha for the open / crossed branch, B = B0 + c e^{i psi}, P = A + p
e^{i arg(B - A)}, then the ground pivot and angle): that four-bar fits them exactly, so the
best known objective is 0. The sets cover the cases of docs/atlas.md: closed curves (a
crank-rocker, a double-crank), an open stretch and a short partial one of a loop, the open
curve of a rocking input (a triple-rocker), from 16 to 150 points, evenly or unevenly spaced
along the input. (closed18_free.toml, the eighteen points of Kunjur & Krishnamurty with
free timing, is written by hand: its best known is a search's.)
"""

from __future__ import annotations

import math
import os

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
FOLDERS = (os.path.join(ROOT, "problems", "bench"), os.path.join(ROOT, "src", "linkcli", "bench_problems"))

CASES = [
    dict(name="free_closed24", title="Closed curve: 24 points around a crank-rocker's coupler curve",
         kind="closed", linkage=dict(ground=4.0, input=1.2, coupler=3.6, output=2.9, point=(1.5, 1.1),
                                     pivot=(10.0, 5.0), angle=25.0, branch="open"),
         inputs=("even", 0.0, 360.0, 24), grashof="crank-rocker", box=40),
    dict(name="free_closed60", title="Closed curve: 60 points around a double-crank's coupler curve, unevenly spaced",
         kind="closed", linkage=dict(ground=1.5, input=3.0, coupler=3.5, output=3.2, point=(2.0, -1.5),
                                     pivot=(-3.0, 2.0), angle=-40.0, branch="crossed"),
         inputs=("uneven", 0.0, 360.0, 60), grashof="double-crank", box=40),
    dict(name="free_closed150", title="Closed curve: 150 points around a crank-rocker's crossing coupler curve",
         kind="closed", linkage=dict(ground=3.0, input=1.0, coupler=3.5, output=3.0, point=(4.0, -1.5),
                                     pivot=(0.0, 0.0), angle=90.0, branch="open"),
         inputs=("uneven", 0.0, 360.0, 150), grashof="crank-rocker", box=40),
    dict(name="free_open40", title="Open stretch: 40 points over 60 % of a crank-rocker's coupler curve",
         kind="open", linkage=dict(ground=5.0, input=1.5, coupler=4.5, output=4.0, point=(3.0, 2.5),
                                   pivot=(2.0, -6.0), angle=10.0, branch="open"),
         inputs=("uneven", 30.0, 246.0, 40), grashof="crank-rocker", box=50),
    dict(name="free_partial16", title="Partial stretch: 16 points over 35 % of a crank-rocker's coupler curve",
         kind="partial", linkage=dict(ground=10.0, input=3.0, coupler=8.0, output=7.0, point=(6.0, 4.0),
                                      pivot=(5.0, 2.0), angle=20.0, branch="open"),
         inputs=("even", 100.0, 226.0, 16), grashof=None, box=40),
    dict(name="free_rocker30", title="Rocking input: 30 points along a triple-rocker's open coupler curve",
         kind="rocking", linkage=dict(ground=4.0, input=2.5, coupler=2.2, output=3.0, point=(1.0, 1.5),
                                      pivot=(-2.0, 3.0), angle=150.0, branch="open"),
         inputs=("arc", 0.9, None, 30), grashof=None, box=30),
]


def coupler(lk: dict, phi: np.ndarray) -> np.ndarray:
    """Global coupler points (complex) of linkage `lk` at input angles phi (rad)."""
    d, a, b, c = lk["ground"], lk["input"], lk["coupler"], lk["output"]
    A = a * np.exp(1j * phi)
    v = A - d
    alpha = np.arccos(np.clip((abs(v) ** 2 + c * c - b * b) / (2 * abs(v) * c), -1.0, 1.0))
    psi = np.angle(v) + (-alpha if lk["branch"] == "open" else alpha)
    B = d + c * np.exp(1j * psi)
    P = A + complex(*lk["point"]) * np.exp(1j * np.angle(B - A))
    return complex(*lk["pivot"]) + np.exp(1j * math.radians(lk["angle"])) * P


def input_angles(case: dict) -> np.ndarray:
    how, lo, hi, n = case["inputs"]
    lk = case["linkage"]
    if how == "arc":  # a share `lo` of the rocking input's arc through 0, centred
        d, a, b, c = lk["ground"], lk["input"], lk["coupler"], lk["output"]
        r = b + c
        g = 2 * math.atan2(math.sqrt(max((r - abs(a - d)) * (r + abs(a - d)), 0.0)),
                           math.sqrt(max((a + d - r) * (a + d + r), 0.0)))
        deg = np.linspace(-lo * g, lo * g, n)
        return deg
    if how == "even":
        step = (hi - lo) / (n if case["kind"] == "closed" else n - 1)
        return np.radians(lo + step * np.arange(n))
    rng = np.random.default_rng(sum(map(ord, case["name"])))
    t = np.sort(rng.uniform(0.0, 1.0, n))
    t = (t - t[0]) / (t[-1] - t[0]) * (0.985 if case["kind"] == "closed" else 1.0)
    return np.radians(lo + (hi - lo) * t)


def text(case: dict) -> str:
    lk = case["linkage"]
    phi = input_angles(case)
    pts = coupler(lk, phi)
    box = case["box"]
    rows = ",\n".join("  [" + f"{p.real:.10f}, {p.imag:.10f}" + "]" for p in pts)
    where = {"even": "evenly", "uneven": "unevenly (seeded)", "arc": "evenly"}[case["inputs"][0]]
    span = (f"{case['inputs'][1]:g} to {case['inputs'][2]:g} deg" if case["inputs"][0] != "arc"
            else f"{case['inputs'][1]:.0%} of its arc through 0 deg, centred")
    source = (f"exact: targets computed (10 decimals) by benchmarks/atlas_targets.py from the {lk['branch']}-branch "
              f"four-bar ground {lk['ground']:g}, input {lk['input']:g}, coupler {lk['coupler']:g}, output "
              f"{lk['output']:g}, coupler point ({lk['point'][0]:g}, {lk['point'][1]:g}), ground pivot "
              f"({lk['pivot'][0]:g}, {lk['pivot'][1]:g}), ground angle {lk['angle']:g} deg, at {len(pts)} input "
              f"angles spaced {where} over {span}")
    head = [f"# {case['title']}, free timing ({case['kind']} target for the coupler-curve atlas, docs/atlas.md).",
            "# Written by benchmarks/atlas_targets.py: " + source.split(": ", 1)[1] + ".",
            "# That four-bar fits the targets exactly; the solver is told none of it.",
            'type = "path-generation"', f'title = "{case["title"]}"', "", "[target]",
            f"points = [\n{rows},\n]", 'timing = "free"', "", "[bounds]"]
    head += [f"{k} = [0, {box}]" for k in ("ground", "input", "coupler", "output")]
    head += [f"coupler_point = {{ x = [-{box}, {box}], y = [-{box}, {box}] }}",
             f"ground_pivot = {{ x = [-{box}, {box}], y = [-{box}, {box}] }}", "ground_angle = [0, 360]", ""]
    if case["grashof"]:
        head += ["[constraints]", f'grashof = "{case["grashof"]}"', ""]
    head += ["[reference]", "objective = 0.0", f'source = "{source}"', ""]
    return "\n".join(head)


def main() -> None:
    for case in CASES:
        body = text(case)
        for folder in FOLDERS:
            with open(os.path.join(folder, case["name"] + ".toml"), "w", encoding="utf-8") as handle:
                handle.write(body)
        print(case["name"], len(input_angles(case)), "points")


if __name__ == "__main__":
    main()
