"""Run every example and bench problem as another CPU would, and compare the JSON.

    python benchmarks/compare_kernels.py [--linkcli CMD] [--jobs N] [FILE...]

Another CPU differs in the OpenBLAS kernel numpy's matrix products and `np.linalg` run
(forced here with OPENBLAS_CORETYPE: Haswell, SkylakeX, Sandybridge, Prescott) and in
numpy's own vector paths for sin, cos, sums and friends (narrowed here to numpy's baseline
with NPY_DISABLE_CPU_FEATURES, every dispatched feature this CPU has; alone and with the
Prescott kernel). Each variant's output is compared with the machine's default;
`solver.evaluations` and times are removed first, since they are the only fields allowed
to differ between machines (docs/determinism.md). Prints one line per
variant and per differing file; exits 1 if any output differs. A variant this CPU cannot
run (SkylakeX needs AVX-512; nothing to narrow on a CPU with numpy's baseline only) is
reported and skipped. The variants run `--jobs` at a time (default 2).
"""

from __future__ import annotations

import argparse
import difflib
import json
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

KERNELS = ["Haswell", "SkylakeX", "Sandybridge", "Prescott"]
ROOT = Path(__file__).resolve().parent.parent
DISPATCHED = """
try:
    from numpy._core._multiarray_umath import __cpu_dispatch__ as d, __cpu_features__ as f
except ImportError:  # numpy 1.x
    from numpy.core._multiarray_umath import __cpu_dispatch__ as d, __cpu_features__ as f
print(",".join(x for x in d if f.get(x)))
"""


def strip(obj):
    """The report without the fields allowed to differ between machines."""
    if isinstance(obj, dict):
        return {k: strip(v) for k, v in obj.items() if k not in ("evaluations", "seconds")}
    if isinstance(obj, list):
        return [strip(v) for v in obj]
    return obj


def variants() -> dict[str, dict]:
    """name -> the environment variables of each variant (the default: none)."""
    simd = subprocess.run([sys.executable, "-c", DISPATCHED], capture_output=True, text=True).stdout.strip()
    out = {"default": {}}
    out.update({kernel: {"OPENBLAS_CORETYPE": kernel} for kernel in KERNELS})
    if simd:
        out["numpy-baseline"] = {"NPY_DISABLE_CPU_FEATURES": simd}
        out["Prescott+numpy-baseline"] = {"OPENBLAS_CORETYPE": "Prescott", "NPY_DISABLE_CPU_FEATURES": simd}
    return out


def run(extra: dict, files: list[str], command: list[str]) -> list | None:
    env = {**os.environ, **extra}
    proc = subprocess.run([*command, "synth", *files, "--format", "json"], capture_output=True,
                          text=True, env=env, cwd=ROOT)
    if proc.returncode < 0 or not proc.stdout.strip():  # e.g. SkylakeX (AVX-512) on a CPU without it
        return None
    return strip(json.loads(proc.stdout))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="*")
    parser.add_argument("--linkcli", default=f"{sys.executable} -m linkcli")
    parser.add_argument("--jobs", type=int, default=2)
    args = parser.parse_args()
    files = args.files or sorted(str(p.relative_to(ROOT)) for p in
                                 [*ROOT.glob("problems/*.toml"), *ROOT.glob("problems/bench/*.toml")])
    command = args.linkcli.split()
    cases = variants()
    if "numpy-baseline" not in cases:
        print("numpy-baseline: numpy runs its baseline vector paths on this CPU already: skipped")
    with ThreadPoolExecutor(max(1, args.jobs)) as pool:
        outputs = dict(zip(cases, pool.map(lambda extra: run(extra, files, command), cases.values())))
    base = outputs["default"]
    differ = 0
    for name in list(cases)[1:]:
        if outputs[name] is None:
            print(f"{name:24s} does not run on this CPU (OpenBLAS stopped): skipped")
            continue
        bad = [f for f, a, b in zip(files, base, outputs[name]) if a != b]
        differ += len(bad)
        print(f"{name:24s} {len(files) - len(bad)}/{len(files)} files identical to the default")
        for f, a, b in zip(files, base, outputs[name]):
            if a != b:
                diff = difflib.unified_diff(json.dumps(a, indent=1).splitlines(),
                                            json.dumps(b, indent=1).splitlines(), lineterm="", n=0)
                shown = [line for line in diff if line[:1] in "+-" and line[:3] not in ("+++", "---")]
                print(f"  {f}: {len(shown) // 2} lines differ, e.g. {' | '.join(shown[:4])}")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
