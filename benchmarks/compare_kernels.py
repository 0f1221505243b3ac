"""Run every example and bench problem under several OpenBLAS kernels and compare the JSON.

    python benchmarks/compare_kernels.py [--linkcli CMD] [FILE...]

Each kernel is forced with OPENBLAS_CORETYPE (Haswell, SkylakeX, Sandybridge, Prescott) next
to the machine's own default; `solver.evaluations` and times are removed before comparing,
since they are the only fields allowed to differ between machines (README, "Golden files").
Prints one line per kernel and per differing file; exits 1 if any output differs. A kernel
the CPU cannot run (SkylakeX needs AVX-512) is reported and skipped.
"""

from __future__ import annotations

import argparse
import difflib
import json
import os
import subprocess
import sys
from pathlib import Path

KERNELS = ["default", "Haswell", "SkylakeX", "Sandybridge", "Prescott"]
ROOT = Path(__file__).resolve().parent.parent


def strip(obj):
    """The report without the fields allowed to differ between machines."""
    if isinstance(obj, dict):
        return {k: strip(v) for k, v in obj.items() if k not in ("evaluations", "seconds")}
    if isinstance(obj, list):
        return [strip(v) for v in obj]
    return obj


def run(kernel: str, files: list[str], command: list[str]) -> list | None:
    env = dict(os.environ)
    if kernel != "default":
        env["OPENBLAS_CORETYPE"] = kernel
    proc = subprocess.run([*command, "synth", *files, "--format", "json"], capture_output=True,
                          text=True, env=env, cwd=ROOT)
    if proc.returncode < 0 or not proc.stdout.strip():  # e.g. SkylakeX (AVX-512) on a CPU without it
        return None
    return strip(json.loads(proc.stdout))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="*")
    parser.add_argument("--linkcli", default=f"{sys.executable} -m linkcli")
    args = parser.parse_args()
    files = args.files or sorted(str(p.relative_to(ROOT)) for p in
                                 [*ROOT.glob("problems/*.toml"), *ROOT.glob("problems/bench/*.toml")])
    command = args.linkcli.split()
    outputs = {k: run(k, files, command) for k in KERNELS}
    base = outputs["default"]
    differ = 0
    for kernel in KERNELS[1:]:
        if outputs[kernel] is None:
            print(f"{kernel:12s} does not run on this CPU (OpenBLAS stopped): skipped")
            continue
        bad = [f for f, a, b in zip(files, base, outputs[kernel]) if a != b]
        differ += len(bad)
        print(f"{kernel:12s} {len(files) - len(bad)}/{len(files)} files identical to the default kernel")
        for f, a, b in zip(files, base, outputs[kernel]):
            if a != b:
                diff = difflib.unified_diff(json.dumps(a, indent=1).splitlines(),
                                            json.dumps(b, indent=1).splitlines(), lineterm="", n=0)
                shown = [line for line in diff if line[:1] in "+-" and line[:3] not in ("+++", "---")]
                print(f"  {f}: {len(shown) // 2} lines differ, e.g. {' | '.join(shown[:4])}")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
