"""Timing-free path generation with and without the coupler-curve atlas, as a user runs it:
each file solved by `linkcli synth FILE -f json --seed S` in a process of its own.

Usage (from the repository root):

    python3 benchmarks/atlas_bench.py [--seeds 3] [--atlas PATH] [FILE...]

Default: every free-timing file of problems/bench. Each run is made twice: as the file says
(the atlas on) and with `[solver] atlas = false` added (a copy of the file in a temporary
folder). For each run: wall seconds of the whole process (start-up, atlas load and search),
its CPU seconds (user + system), its peak resident memory, status, objective and the gap to
the file's `[reference] objective`. Then per setting the median and maximum wall seconds
and how many runs ended `ok` at (within 1e-6, relative, or 1e-12 of the targets' extent
squared for a best known of 0) or below the best known. The atlas must be built first
(`linkcli atlas build`); --atlas uses another atlas file (LINKCLI_ATLAS).
"""

from __future__ import annotations

import argparse
import glob
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
import tomllib


def free_timing(path: str) -> bool:
    with open(path, "rb") as handle:
        data = tomllib.load(handle)
    return data.get("type") == "path-generation" and data.get("target", {}).get("timing") == "free" \
        and "linkage" not in data


def reference(path: str) -> tuple[float | None, float, int]:
    """(best known objective or None, the floor a best known of 0 is met within: 1e-12 of the
    targets' extent squared a point, the number of points)."""
    with open(path, "rb") as handle:
        data = tomllib.load(handle)
    pts = data["target"]["points"]
    extent = max(max(p[k] for p in pts) - min(p[k] for p in pts) for k in (0, 1))
    return data.get("reference", {}).get("objective"), 1e-12 * extent ** 2 * len(pts), len(pts)


def without_atlas(path: str, folder: str) -> str:
    with open(path, encoding="utf-8") as handle:
        text = handle.read()
    if "[solver]" in text:
        text = text.replace("[solver]", "[solver]\natlas = false", 1)
    else:
        text += "\n[solver]\natlas = false\n"
    out = os.path.join(folder, os.path.basename(path))
    with open(out, "w", encoding="utf-8") as handle:
        handle.write(text)
    return out


def run(path: str, seed: int, env: dict) -> dict:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    res = subprocess.run([sys.executable, "-m", "linkcli", "synth", path, "-f", "json", "--seed", str(seed),
                          "--precision", "10"], capture_output=True, text=True, env=env)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    try:
        report = json.loads(res.stdout)
        status, objective = report["status"], report["error"]["objective"]
        evaluations = report["solver"]["evaluations"]
    except (ValueError, KeyError, TypeError):
        status, objective, evaluations = f"error (exit {res.returncode})", float("inf"), None
    return {"wall": wall, "cpu": cpu, "status": status, "objective": objective, "evaluations": evaluations,
            "stderr": res.stderr.strip()[-300:]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("files", nargs="*")
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--atlas", default=None, help="an atlas file (LINKCLI_ATLAS)")
    args = ap.parse_args()
    files = args.files or [f for f in sorted(glob.glob("problems/bench/*.toml")) if free_timing(f)]
    env = dict(os.environ)
    if args.atlas:
        env["LINKCLI_ATLAS"] = args.atlas
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for path in files:
            best, floor, points = reference(path)
            for label, target in (("atlas", path), ("no atlas", without_atlas(path, folder))):
                for seed in range(args.seeds):
                    r = run(target, seed, env)
                    r.update(problem=os.path.splitext(os.path.basename(path))[0], setting=label, seed=seed,
                             best=best, points=points,
                             at_best=best is not None and r["objective"] <= max(best * (1 + 1e-6), floor))
                    rows.append(r)
                    print(f"{r['problem']:16s} {label:8s} seed {seed}: {r['wall']:6.2f} s wall {r['cpu']:6.2f} s cpu "
                          f"{r['status']:13s} {r['objective']:.10g} (best {best})"
                          + (f"  [{r['stderr']}]" if r["stderr"] else ""), flush=True)
    print()
    print("| problem | points | setting | runs ok at best | median s | max s | median cpu s | max cpu s |")
    print("|---|---|---|---|---|---|---|---|")
    for problem in dict.fromkeys(r["problem"] for r in rows):
        for label in ("atlas", "no atlas"):
            rs = [r for r in rows if r["problem"] == problem and r["setting"] == label]
            ok = sum(r["status"] == "ok" and r["at_best"] for r in rs)
            print(f"| {problem} | {rs[0]['points']} | {label} | {ok}/{len(rs)} | {statistics.median(r['wall'] for r in rs):.2f} | "
                  f"{max(r['wall'] for r in rs):.2f} | {statistics.median(r['cpu'] for r in rs):.2f} | "
                  f"{max(r['cpu'] for r in rs):.2f} |")
    for label in ("atlas", "no atlas"):
        rs = [r for r in rows if r["setting"] == label]
        print(f"{label}: median {statistics.median(r['wall'] for r in rs):.2f} s, max {max(r['wall'] for r in rs):.2f} s "
              f"wall; median {statistics.median(r['cpu'] for r in rs):.2f} s cpu; "
              f"{sum(r['status'] == 'ok' and r['at_best'] for r in rs)}/{len(rs)} ok at the best known")


if __name__ == "__main__":
    main()
