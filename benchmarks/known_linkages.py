"""Path generation on targets taken from the coupler curves of known random four-bars.

Usage (from the repository root):

    python3 benchmarks/known_linkages.py [--cases 100] [--seed 0] [--out FILE] [--only I ...]

Case i is drawn with numpy.random.default_rng([seed, i]) (the same case whatever --cases):
a four-bar of a random Grashof class (crank-rocker, double-crank, rocker-crank,
double-rocker, or non-Grashof = triple-rocker), a coupler point, ground pivot, ground
angle and branch; units mm, cm, m or in (lengths scaled to the unit) and deg or rad;
4 to 20 unevenly spaced targets on its coupler curve, within the input's range of motion
(a rocking input: inside one reachable arc, away from its dead points); timing prescribed
(absolute angles, or relative with a free input_offset) or free (direction either or the
true one); bounds that contain the true linkage. Each case is written as a TOML file to a
temporary directory and solved by `linkcli synth FILE -f json --precision 17 --timing`
(one process at a time; --precision 17 so that the reported linkage can be checked).

Each report is then checked here, independently of linkcli's code, from the conventions of
docs/format.md (numpy complex numbers): the coupler point of the REPORTED linkage at the
REPORTED input angles, the objective sum |P_k - T_k|^2, assembly at every target, no dead
point over the input's travel from the first target to the last (exact extremes of |A B0|),
targets in order within one turn (free timing), the prescribed angles plus the offset, the
bounds, the Grashof class and the branch asked for. A false claim: an `ok` whose recomputed
objective exceeds 1e-10 of the targets' extent squared, an `ok` the check finds a defect in,
an `infeasible` the check finds none in, a reported objective or achieved point the check
does not reproduce, or an exit code that does not match the status.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
import scipy

CLASSES = ("crank-rocker", "double-crank", "rocker-crank", "double-rocker", "triple-rocker")
SHORTEST = {"crank-rocker": "input", "double-crank": "ground", "rocker-crank": "output",
            "double-rocker": "coupler"}
LINKS = ("ground", "input", "coupler", "output")
UNIT_SCALE = {"mm": (20.0, 300.0), "cm": (2.0, 30.0), "m": (0.05, 3.0), "in": (1.0, 12.0)}
EXACT, SMALL = 1e-20, 1e-10  # objective / extent^2 thresholds


# ---------------------------------------------------------------- the independent kinematics

def closure(lk: dict, phi: np.ndarray):
    """Global coupler points (complex) and cos(alpha) of linkage `lk` (lengths, branch,
    coupler_point, ground_pivot, ground_angle in rad) at input angles phi (rad), from
    docs/format.md: A0 at the origin, B0 = d on the ground line; A = a e^{i phi}; rho = |A B0|,
    alpha the angle at B0 between B0 -> A and B0 -> B, psi = arg(A - B0) -/+ alpha for the
    open / crossed branch; B = B0 + c e^{i psi}; P = A + (px + i py) e^{i theta}, theta =
    arg(B - A); X = ground_pivot + e^{i ground_angle} P."""
    d, a, b, c = (lk[k] for k in LINKS)
    A = a * np.exp(1j * np.asarray(phi, dtype=float))
    v = A - d
    rho = np.abs(v)
    cos_alpha = (rho * rho + c * c - b * b) / (2 * rho * c)
    alpha = np.arccos(np.clip(cos_alpha, -1.0, 1.0))
    psi = np.angle(v) + (-alpha if lk["branch"] == "open" else alpha)
    B = d + c * np.exp(1j * psi)
    e = np.exp(1j * np.angle(B - A))
    P = A + complex(*lk["coupler_point"]) * e
    return complex(*lk["ground_pivot"]) + np.exp(1j * lk["ground_angle"]) * P, cos_alpha


def grashof_class(lk: dict) -> str:
    """The Grashof class of docs/format.md (change point within a relative 1e-9)."""
    lengths = {k: lk[k] for k in LINKS}
    s, l = min(lengths.values()), max(lengths.values())
    pq = sum(lengths.values()) - s - l
    if abs(s + l - pq) <= 1e-9 * (s + l):
        return "change-point"
    if s + l > pq:
        return "triple-rocker"
    shortest = min(lengths, key=lengths.get)
    return {v: k for k, v in SHORTEST.items()}[shortest]


def reachable_arcs(lk: dict) -> list[tuple[float, float]]:
    """The arcs (start, width) in rad of input angles at which the loop closes:
    rho^2 = a^2 + d^2 - 2 a d cos(phi) within [(b - c)^2, (b + c)^2]."""
    d, a, b, c = (lk[k] for k in LINKS)
    lo = (a * a + d * d - (b + c) ** 2) / (2 * a * d)  # cos(phi) >= lo
    hi = (a * a + d * d - (b - c) ** 2) / (2 * a * d)  # cos(phi) <= hi
    if lo > 1 or hi < -1:
        return []
    p1, p2 = math.acos(min(hi, 1.0)), math.acos(max(lo, -1.0))
    if p1 == 0 and p2 == math.pi:
        return [(-math.pi, 2 * math.pi)]
    if p1 == 0:
        return [(-p2, 2 * p2)]
    if p2 == math.pi:
        return [(p1, 2 * (math.pi - p1))]
    return [(p1, p2 - p1), (-p2, p2 - p1)]


def travel_is_clear(lk: dict, t0: float, t1: float) -> bool:
    """No dead point for inputs between t0 and t1 (rad): |A B0| stays within
    [|b - c|, b + c] (its extremes are at the ends and where phi = 0 or pi mod 2 pi)."""
    d, a, b, c = (lk[k] for k in LINKS)
    lo, hi = min(t0, t1), max(t0, t1)
    cosines = [math.cos(lo), math.cos(hi)]
    if math.floor(hi / (2 * math.pi)) * 2 * math.pi >= lo:
        cosines.append(1.0)
    if math.floor((hi - math.pi) / (2 * math.pi)) * 2 * math.pi + math.pi >= lo:
        cosines.append(-1.0)
    rho2 = [a * a + d * d - 2 * a * d * x for x in cosines]
    tol = 1e-12 * (b + c) ** 2
    return min(rho2) >= (b - c) ** 2 - tol and max(rho2) <= (b + c) ** 2 + tol


# ---------------------------------------------------------------- drawing a case

def draw_lengths(rng, cls: str) -> dict:
    """Normalized lengths (longest about 1) of class `cls`, 5 % away from a change point;
    a rocking input keeps at least 20 deg of reachable arc."""
    while True:
        if cls == "triple-rocker":
            v = rng.uniform(0.35, 1.0, 4)
            ok = v.min() + v.max() >= 1.05 * (v.sum() - v.min() - v.max())
            lk = dict(zip(LINKS, v))
        else:
            others = rng.uniform(0.55, 1.0, 3)
            s = rng.uniform(0.2, 0.45)
            ok = s + others.max() <= 0.95 * (others.sum() - others.max())
            rest = iter(others)
            lk = {k: (s if k == SHORTEST[cls] else next(rest)) for k in LINKS}
        if ok and grashof_class(lk) == cls:
            arcs = reachable_arcs(lk)
            if arcs and max(w for _, w in arcs) >= math.radians(20):
                return {k: float(x) for k, x in lk.items()}


def draw_inputs(rng, lk: dict, n: int) -> np.ndarray:
    """n input angles (rad) in the order of motion, unevenly spaced, within one reachable
    arc (a rocker: 3 % of the arc kept clear at each dead point); a full turn: a sweep of
    60 to 340 deg."""
    arcs = reachable_arcs(lk)
    start, width = arcs[rng.integers(len(arcs))]
    if width >= 2 * math.pi:
        sweep = math.radians(rng.uniform(60, 340))
        first = rng.uniform(-math.pi, math.pi)
    else:
        margin = 0.03 * width
        usable = width - 2 * margin
        sweep = rng.uniform(0.35, 0.95) * usable
        first = start + margin + rng.uniform(0, usable - sweep)
    gaps = rng.uniform(0.2, 1.8, n - 1)
    phi = first + sweep * np.concatenate([[0.0], np.cumsum(gaps) / gaps.sum()])
    return phi[::-1].copy() if rng.random() < 0.5 else phi


def around(rng, value: float, scale: float) -> list[float]:
    """A range containing value, 0.2 to 1.5 scale wide on each side."""
    return [value - scale * rng.uniform(0.2, 1.5), value + scale * rng.uniform(0.2, 1.5)]


def length_bounds(rng, lk: dict) -> dict:
    """Per link [0.5 x, 2 x] or [0, 5 x]: all tight, all wide or mixed."""
    mode = rng.choice(["tight", "wide", "mixed"])
    out = {}
    for k in LINKS:
        wide = mode == "wide" or (mode == "mixed" and rng.random() < 0.5)
        out[k] = [0.0, 5 * lk[k]] if wide else [0.5 * lk[k], 2 * lk[k]]
    return out


def angle_range(rng, true_deg: float) -> list[float]:
    """A ground angle or offset range (deg): a full turn either way, or a window around the truth."""
    pick = rng.integers(3)
    if pick == 0:
        return [0.0, 360.0]
    if pick == 1:
        return [-180.0, 180.0]
    return [true_deg - rng.uniform(5, 90), true_deg + rng.uniform(5, 90)]


def draw_case(seed: int, index: int) -> dict:
    """Case `index` of the study: the true linkage (lengths in the file's unit, angles in
    rad), the targets and everything the TOML file needs (angles in deg)."""
    rng = np.random.default_rng([seed, index])
    cls = CLASSES[rng.integers(len(CLASSES))]
    length_unit = str(rng.choice(list(UNIT_SCALE)))
    angle_unit = str(rng.choice(["deg", "rad"]))
    scale = rng.uniform(*UNIT_SCALE[length_unit])
    norm = draw_lengths(rng, cls)
    lk = {k: v * scale for k, v in norm.items()}
    lk["branch"] = str(rng.choice(["open", "crossed"]))
    while True:
        px, py = rng.uniform(-0.8, 1.2), rng.uniform(-0.8, 0.8)
        if math.hypot(px, py) >= 0.1:
            break
    lk["coupler_point"] = [px * scale, py * scale]
    lk["ground_pivot"] = list(rng.uniform(-1.5, 1.5, 2) * scale)
    lk["ground_angle"] = rng.uniform(-math.pi, math.pi)
    n = int(rng.integers(4, 21))
    phi = draw_inputs(rng, lk, n)
    pts, _ = closure(lk, phi)
    timing = str(rng.choice(["prescribed", "offset", "free"]))
    case = dict(index=index, cls=cls, length_unit=length_unit, angle_unit=angle_unit, lk=lk,
                phi=phi, points=np.stack([pts.real, pts.imag], axis=1), timing=timing,
                direction="ccw" if phi[-1] > phi[0] else "cw")
    phi_deg = np.degrees(phi)
    if timing == "prescribed":
        case["written"] = phi_deg
    elif timing == "offset":
        r0 = 0.0 if rng.random() < 0.5 else rng.uniform(-180, 180)
        case["written"] = phi_deg - phi_deg[0] + r0
        true_offset = (phi_deg[0] - r0 + 180.0) % 360.0 - 180.0
        case["offset_range"] = angle_range(rng, true_offset)
    else:
        case["free_direction"] = "either" if rng.random() < 0.5 else case["direction"]
    case["bounds"] = length_bounds(rng, lk)
    case["coupler_box"] = [around(rng, v, scale) for v in lk["coupler_point"]]
    case["pivot_box"] = [around(rng, v, scale) for v in lk["ground_pivot"]]
    case["ground_range"] = angle_range(rng, math.degrees(lk["ground_angle"]))
    case["grashof"] = cls if rng.random() < 0.8 else "any"
    case["branch"] = lk["branch"] if rng.random() < 0.5 else "either"
    return case


# ---------------------------------------------------------------- the TOML file

def num(v: float) -> str:
    """A float at full precision, as TOML reads it back."""
    return repr(float(v))


def arr(values, angle: bool = False, rad: bool = False) -> str:
    """A TOML array of numbers; degree values converted when the file is in rad."""
    return "[" + ", ".join(num(math.radians(v) if angle and rad else v) for v in values) + "]"


def toml_text(case: dict) -> str:
    """The problem file of a case."""
    rad = case["angle_unit"] == "rad"
    pts = ", ".join(f"[{num(x)}, {num(y)}]" for x, y in case["points"])
    lines = ['type = "path-generation"',
             f'title = "known linkage {case["index"]}: {case["cls"]}, {case["lk"]["branch"]}"',
             "", "[units]", f'length = "{case["length_unit"]}"', f'angle = "{case["angle_unit"]}"',
             "", "[target]", f"points = [{pts}]"]
    if case["timing"] == "free":
        lines += ['timing = "free"', f'direction = "{case["free_direction"]}"']
    else:
        lines += ['timing = "prescribed"', f"input_angles = {arr(case['written'], True, rad)}"]
    lines += ["", "[bounds]"] + [f"{k} = {arr(case['bounds'][k])}" for k in LINKS]
    cp, gp = case["coupler_box"], case["pivot_box"]
    lines += [f"coupler_point = {{ x = {arr(cp[0])}, y = {arr(cp[1])} }}",
              f"ground_pivot = {{ x = {arr(gp[0])}, y = {arr(gp[1])} }}",
              f"ground_angle = {arr(case['ground_range'], True, rad)}"]
    if case["timing"] == "offset":
        lines.append(f"input_offset = {arr(case['offset_range'], True, rad)}")
    lines += ["", "[constraints]", f'grashof = "{case["grashof"]}"', f'branch = "{case["branch"]}"']
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------- solving

def linkcli_command() -> list[str]:
    """The linkcli executable of this environment."""
    exe = shutil.which("linkcli")
    return [exe] if exe else [sys.executable, "-m", "linkcli"]


def solve(path: str) -> dict:
    """Run `linkcli synth` on one file: exit code, wall seconds, the parsed report (or None)."""
    cmd = linkcli_command() + ["synth", path, "-f", "json", "--precision", "17", "--timing"]
    t0 = time.perf_counter()
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=1800)
    except subprocess.TimeoutExpired:
        return dict(code=None, seconds=time.perf_counter() - t0, report=None, stderr="timeout")
    seconds = time.perf_counter() - t0
    try:
        report = json.loads(proc.stdout)
    except json.JSONDecodeError:
        report = None
    return dict(code=proc.returncode, seconds=seconds, report=report, stderr=proc.stderr.strip())


# ---------------------------------------------------------------- the check

def extent(points: np.ndarray) -> float:
    """The targets' extent: the larger side of their bounding box."""
    return float(np.max(points.max(axis=0) - points.min(axis=0)))


def in_range(value: float, lo: float, hi: float) -> bool:
    """lo <= value <= hi, with a relative 1e-9 of the range or value; a lower bound of 0 is strict."""
    tol = 1e-9 * max(abs(hi - lo), abs(lo), abs(hi))
    return (value > 0 if lo == 0 else value >= lo - tol) and value <= hi + tol


def in_angle_range(value_deg: float, lo: float, hi: float) -> bool:
    """value (mod a turn) within [lo, hi] (deg)."""
    return hi - lo >= 360 - 1e-9 or (value_deg - lo) % 360.0 <= hi - lo + 1e-9


def bound_defects(case: dict, lk: dict, offset_deg) -> list[str]:
    """Names of the bounds the reported linkage (lengths in the unit, angles in rad) breaks."""
    bad = [k for k in LINKS if not in_range(lk[k], *case["bounds"][k])]
    bad += [f"coupler_point.{ax}" for ax, v, r in zip("xy", lk["coupler_point"], case["coupler_box"])
            if not in_range(v, *r)]
    bad += [f"ground_pivot.{ax}" for ax, v, r in zip("xy", lk["ground_pivot"], case["pivot_box"])
            if not in_range(v, *r)]
    if not in_angle_range(math.degrees(lk["ground_angle"]), *case["ground_range"]):
        bad.append("ground_angle")
    if offset_deg is not None and not in_range(offset_deg, *case["offset_range"]) \
            and not (case["offset_range"][1] - case["offset_range"][0] >= 360
                     and in_angle_range(offset_deg, *case["offset_range"])):
        bad.append("input_offset")
    return ["bounds: " + b for b in bad]


def travel(case: dict, report: dict, inputs_deg: np.ndarray, defects: list[str]):
    """(first, last) input of the travel (deg), checking the timing against the file:
    prescribed angles plus the reported offset, or free targets in order within one turn."""
    if case["timing"] != "free":
        offset = report["timing"].get("input_offset", 0.0) if case["timing"] == "offset" else 0.0
        if case["timing"] == "offset":
            offset = math.degrees(offset) if case["angle_unit"] == "rad" else offset
        expected = case["written"] + offset
        if np.max(np.abs((inputs_deg - expected + 180.0) % 360.0 - 180.0)) > 1e-7:
            defects.append("timing: inputs are not the prescribed angles + offset")
        return expected[0], expected[-1]
    s = 1.0 if report["timing"]["direction"] == "ccw" else -1.0
    if case["free_direction"] != "either" and report["timing"]["direction"] != case["free_direction"]:
        defects.append("direction")
    steps = (s * np.diff(inputs_deg)) % 360.0
    if np.any(steps <= 0) or steps.sum() >= 360.0:
        defects.append(f"order: increments sum to {steps.sum():.6g} deg")
    return inputs_deg[0], inputs_deg[0] + s * steps.sum()


def check(case: dict, report: dict) -> dict:
    """Recompute the reported linkage at the reported inputs: objective, agreement with the
    report, and every defect the check finds."""
    rad = case["angle_unit"] == "rad"
    to_deg = math.degrees if rad else float
    rl = report["linkage"]
    lk = {k: float(rl[k]) for k in LINKS}
    lk.update(branch=rl["branch"], coupler_point=list(rl["coupler_point"]),
              ground_pivot=list(rl["ground_pivot"]), ground_angle=math.radians(to_deg(rl["ground_angle"])))
    inputs_deg = np.array([to_deg(r["input"]) for r in report["positions"]])
    X, cos_alpha = closure(lk, np.radians(inputs_deg))
    T = case["points"][:, 0] + 1j * case["points"][:, 1]
    E = extent(case["points"])
    objective = float(np.sum(np.abs(X - T) ** 2))
    achieved = np.array([complex(*r["achieved"]) for r in report["positions"]])
    targets_echoed = np.allclose([complex(*r["target"]) for r in report["positions"]], T, rtol=0, atol=1e-12 * E)
    rep_obj = float(report["error"]["objective"])
    agree = (abs(rep_obj - objective) <= 1e-6 * max(rep_obj, objective) + EXACT * E * E
             and float(np.max(np.abs(achieved - X))) <= 1e-9 * E and targets_echoed)
    defects = [f"assembly at target {k + 1}" for k in np.flatnonzero(np.abs(cos_alpha) > 1 + 1e-12)]
    first, last = travel(case, report, inputs_deg, defects)
    if not travel_is_clear(lk, math.radians(first), math.radians(last)):
        defects.append("dead point between the first and the last target")
    offset = report["timing"].get("input_offset") if case["timing"] == "offset" else None
    defects += bound_defects(case, lk, None if offset is None else to_deg(offset))
    own = grashof_class(lk)
    if case["grashof"] != "any" and own != case["grashof"]:
        defects.append(f"class: {own}, not {case['grashof']}")
    if case["branch"] != "either" and lk["branch"] != case["branch"]:
        defects.append("branch")
    return dict(objective=objective, ratio=objective / (E * E), agree=agree,
                rel_diff=abs(rep_obj - objective) / max(rep_obj, objective, EXACT * E * E),
                defects=defects, own_class=own)


def verdict(run: dict, chk: dict | None) -> list[str]:
    """The false claims of one run (empty: the report says what the check finds)."""
    rep = run["report"]
    if rep is None:
        return []
    status, claims = rep["status"], []
    expected_code = 0 if status == "ok" else 1
    if run["code"] != expected_code:
        claims.append(f"exit code {run['code']} with status {status}")
    if chk is None:
        return claims
    if not chk["agree"]:
        claims.append("reported objective / achieved points not reproduced")
    if status == "ok" and chk["ratio"] > SMALL:
        claims.append("ok but objective not small")
    if status == "ok" and chk["defects"]:
        claims.append("ok with defects: " + "; ".join(chk["defects"]))
    if status == "infeasible" and not chk["defects"]:
        claims.append("infeasible, but the check finds every constraint met")
    return claims


# ---------------------------------------------------------------- the study

def run_case(case: dict, folder: str) -> dict:
    """Write, solve and check one case."""
    text = toml_text(case)
    path = os.path.join(folder, f"case{case['index']:03d}.toml")
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(text)
    run = solve(path)
    rep = run["report"]
    chk = check(case, rep) if rep is not None and "positions" in rep else None
    return dict(case=case, text=text, run=run, check=chk, claims=verdict(run, chk),
                status=rep["status"] if rep else f"error (exit {run['code']})",
                solve_seconds=(rep or {}).get("solver", {}).get("seconds"))


def timing_label(case: dict) -> str:
    """prescribed / prescribed+offset / free-<direction>."""
    return {"prescribed": "prescribed", "offset": "prescribed+offset"}.get(
        case["timing"], f"free-{case.get('free_direction')}")


def row(res: dict) -> str:
    """One markdown row of the per-case table."""
    c, chk = res["case"], res["check"]
    ratio = "-" if chk is None else f"{chk['ratio']:.2e}"
    agree = "-" if chk is None else ("yes" if chk["agree"] else f"NO ({chk['rel_diff']:.1e})")
    found = "-" if chk is None or not chk["defects"] else "; ".join(chk["defects"])
    claim = "; ".join(res["claims"]) or "-"
    solve_s = "-" if res["solve_seconds"] is None else f"{res['solve_seconds']:.2f}"
    return (f"| {c['index']} | {c['cls']} | {c['lk']['branch']} | {c['length_unit']}/{c['angle_unit']} | "
            f"{timing_label(c)} | {len(c['points'])} | {res['status']} | {ratio} | {agree} | {found} | "
            f"{claim} | {res['run']['seconds']:.2f} | {solve_s} |")


def machine() -> str:
    """Platform, CPU count, Python, numpy, scipy and linkcli versions."""
    version = subprocess.run(linkcli_command() + ["--version"], capture_output=True, text=True).stdout.strip()
    return (f"{platform.platform()}, {platform.machine()}, {os.cpu_count()} cores, Python "
            f"{platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}, {version}")


def true_linkage(case: dict) -> str:
    """The linkage the targets were taken from, in one line."""
    lk = case["lk"]
    return ", ".join(f"{k} {lk[k]!r}" if not isinstance(lk[k], list) else f"{k} {[float(v) for v in lk[k]]}"
                     for k in (*LINKS, "branch", "coupler_point", "ground_pivot", "ground_angle")) \
        + f", inputs {[float(v) for v in case['phi']]}"


def needs_a_look(res: dict) -> bool:
    """A case that is not an exact `ok` (or has a false claim)."""
    chk = res["check"]
    return bool(res["claims"]) or res["status"] != "ok" or chk is None or chk["ratio"] > SMALL


def summary(results: list[dict], args) -> str:
    """The markdown report: per-case table, totals, machine, the TOML of the cases to look at."""
    n = len(results)
    ratios = [r["check"]["ratio"] for r in results if r["check"] is not None]
    secs = [r["run"]["seconds"] for r in results]
    look = [r for r in results if needs_a_look(r)]
    head = ("| case | class | branch | units | timing | n | status | objective / extent^2 | "
            "recomputed agrees | check finds | false claim | wall s | solve s |\n" + "|---" * 13 + "|\n")
    lines = ["# Path generation on known linkages\n",
             f"Reproduce: `python3 benchmarks/known_linkages.py --cases {args.cases} --seed {args.seed}"
             + (f" --only {' '.join(map(str, args.only))}" if args.only else "") + "`. "
             "Classes: triple-rocker is the non-Grashof class. "
             "Targets on the coupler curve of a random known four-bar (in the bounds), solved by "
             "`linkcli synth FILE -f json --precision 17 --timing`, one process at a time; checked by an "
             "independent closure (numpy, docs/format.md). extent = larger side of the targets' "
             "bounding box. wall s: the subprocess, start-up included; solve s: the report's "
             "`solver.seconds`.\n", "## Cases\n", head + "\n".join(row(r) for r in results) + "\n",
             "## Totals\n",
             f"- cases: {n}",
             f"- objective below 1e-10 of extent^2: {sum(x < SMALL for x in ratios)} of {n}",
             f"- objective below 1e-20 of extent^2: {sum(x < EXACT for x in ratios)} of {n}",
             f"- status `ok`: {sum(r['status'] == 'ok' for r in results)} of {n}"
             + "".join(f"; `{s}`: {sum(r['status'] == s for r in results)}"
                       for s in sorted({r['status'] for r in results} - {'ok'})),
             f"- recomputed objective and points agree with the report: "
             f"{sum(r['check'] is not None and r['check']['agree'] for r in results)} of {n}",
             f"- false claims: {sum(bool(r['claims']) for r in results)}",
             f"- wall seconds: median {statistics.median(secs):.2f}, max {max(secs):.2f}, "
             f"total {sum(secs):.0f}",
             f"- machine: {machine()}\n"]
    if look:
        lines.append("## Cases that are not an exact `ok`, or a false claim\n")
        for r in look:
            lines.append(f"### case {r['case']['index']}: {r['status']}, objective / extent^2 = "
                         + ("-" if r["check"] is None else f"{r['check']['ratio']:.3e}")
                         + (f", false claim: {'; '.join(r['claims'])}" if r["claims"] else "")
                         + (f"\n\nstderr: `{r['run']['stderr'][:300]}`" if r["run"]["report"] is None else "")
                         + f"\n\nTrue linkage (angles in rad): {true_linkage(r['case'])}"
                         + f"\n\n```toml\n{r['text']}```\n")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", type=int, default=100)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default="benchmarks/KNOWN_LINKAGES.md")
    ap.add_argument("--only", type=int, nargs="+", default=None, help="run these case indices only")
    args = ap.parse_args()
    indices = args.only if args.only else range(args.cases)
    results = []
    with tempfile.TemporaryDirectory(prefix="known_linkages_") as folder:
        for i in indices:
            res = run_case(draw_case(args.seed, i), folder)
            results.append(res)
            print(row(res), file=sys.stderr, flush=True)
    text = summary(results, args)
    print(text)
    with open(args.out, "w", encoding="utf-8") as fh:
        fh.write(text)


if __name__ == "__main__":
    main()
