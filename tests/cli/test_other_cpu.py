"""The examples print the same bytes on another CPU, simulated on this one.

Two machines differ in the OpenBLAS kernel that numpy's matrix products and `np.linalg`
run (chosen by CPU; OPENBLAS_CORETYPE forces one) and in numpy's own vector paths for
sin, cos, sums and friends (chosen by CPU; NPY_DISABLE_CPU_FEATURES narrows them). Every
example in problems/ (and bench/log_generator_grashof.toml, whose status once followed the
kernel, a seven-pose motion search that starts from four-pose curves, and a twelve-pose one whose settle walks
first) is solved three times in subprocesses: as this environment runs it, under a
second OpenBLAS kernel, and with numpy's dispatched vector paths all disabled; each
output must equal the first byte for byte (JSON, every number and status), but for the
solver's evaluation count (machine_fields.py), with the same exit code and stderr.
A variant this machine cannot run is skipped with the reason: a kernel the CPU lacks the
instructions for, numpy already at its baseline, a BLAS that is not OpenBLAS.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

import pytest
from conftest import ROOT
from machine_fields import MASK, masked

FILES = sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "problems").glob("*.toml")) + [
    "problems/bench/log_generator_grashof.toml",
    "tests/data/motion_seven_poses_length.toml",  # motion's four-pose curve starts (SVDs in their polish)
    "tests/data/motion_window_long_valley.toml"]  # motion's walk to the optimum (BLAS and NNLS steps)
KERNELS = ("Prescott", "Sandybridge", "Haswell")  # x86-64 kernels, oldest first: another one runs
MACHINE = ("OPENBLAS_CORETYPE", "NPY_DISABLE_CPU_FEATURES")

pytestmark = pytest.mark.slow  # every example under other CPUs: the full suite runs them, the fast lane does not

PROBE = r"""
import ctypes, json, numpy as np, numpy.linalg
try:
    from numpy._core._multiarray_umath import __cpu_dispatch__ as dispatch, __cpu_features__ as features
except ImportError:  # numpy 1.x
    from numpy.core._multiarray_umath import __cpu_dispatch__ as dispatch, __cpu_features__ as features
kernel = None
try:
    libs = {line.split()[-1] for line in open("/proc/self/maps") if "openblas" in line.lower()}
    for lib in sorted(libs):
        for name in ("scipy_openblas_get_corename64_", "openblas_get_corename64_", "openblas_get_corename"):
            fn = getattr(ctypes.CDLL(lib), name, None)
            if fn is not None:
                fn.restype = ctypes.c_char_p
                kernel = fn().decode()
                break
except OSError:
    pass
np.ones((8, 8)) @ np.ones((8, 8))
print(json.dumps({"kernel": kernel, "simd": [f for f in dispatch if features.get(f)]}))
"""


def environment(**extra) -> dict:
    env = dict(os.environ)
    env.update(extra)
    return env


def probe(env: dict) -> dict | None:
    """The OpenBLAS kernel and numpy's enabled dispatched vector paths under env; None
    when Python dies there (a kernel whose instructions the CPU lacks)."""
    proc = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True, env=env, timeout=120)
    return json.loads(proc.stdout) if proc.returncode == 0 else None


def synth(env: dict):
    # timeout: a hang guard, not a time limit (every example, three runs side by side)
    proc = subprocess.run([sys.executable, "-m", "linkcli", "synth", *FILES, "--format", "json"],
                          capture_output=True, text=True, env=env, cwd=ROOT, timeout=3600)
    return proc.returncode, proc.stdout, proc.stderr


def variants() -> dict[str, dict | str]:
    """name -> the environment of a variant this machine can run, or why it cannot."""
    here = probe(environment())
    out: dict[str, dict | str] = {}
    if here is None or here["kernel"] is None:
        out["kernel"] = "numpy's BLAS is not an OpenBLAS whose kernel can be read"
    else:
        out["kernel"] = f"no other x86-64 OpenBLAS kernel runs here (this one: {here['kernel']})"
        for kernel in KERNELS:
            env = environment(OPENBLAS_CORETYPE=kernel)
            there = probe(env)
            if there is not None and there["kernel"] not in (None, here["kernel"]):
                out["kernel"] = env
                break
    if here is None or not here["simd"]:
        out["simd"] = "numpy runs its baseline vector paths already"
    else:
        env = environment(NPY_DISABLE_CPU_FEATURES=",".join(here["simd"]))
        there = probe(env)
        out["simd"] = env if there is not None and not there["simd"] else "numpy would not disable " + \
            ", ".join(here["simd"])
    return out


@pytest.fixture(scope="module")
def runs():
    """The examples' output here and under each variant, the subprocesses side by side."""
    cases = {"here": environment(), **variants()}
    todo = {name: env for name, env in cases.items() if isinstance(env, dict)}
    with ThreadPoolExecutor(len(todo)) as pool:
        done = dict(zip(todo, pool.map(synth, todo.values())))
    return {name: done.get(name, why) for name, why in cases.items()}


# An open defect, not a tolerance: the file's report moves under another CPU. Its test below is
# a strict xfail, so it fails (and must leave this list) the day the file prints the same bytes.
KNOWN_TO_DIFFER: dict[str, str] = {}  # path -> why it differs (none is known)


def _reports(runs, variant):
    if isinstance(runs[variant], str):
        pytest.skip(runs[variant])
    code, out, err = runs["here"]
    code2, out2, err2 = runs[variant]
    assert code in (0, 1) and out.startswith("["), err
    assert (code2, err2) == (code, err)
    return dict(zip(FILES, zip(json.loads(masked(out, "json")), json.loads(masked(out2, "json")))))


@pytest.mark.parametrize("variant", ["kernel", "simd"])
def test_the_examples_print_the_same_bytes_on_another_cpu(runs, variant):
    for path, (a, b) in _reports(runs, variant).items():
        if path not in KNOWN_TO_DIFFER:
            assert a == b, f"{path} differs under the {variant} variant"


@pytest.mark.xfail(strict=True, reason="; ".join(KNOWN_TO_DIFFER.values()))
def test_the_known_differences_are_still_there(runs):
    if not KNOWN_TO_DIFFER:
        pytest.skip("no example is known to differ")
    variants = [_reports(runs, variant) for variant in ("kernel", "simd")]
    assert all(reports[path][0] == reports[path][1] for reports in variants for path in KNOWN_TO_DIFFER)


def test_the_mask_hides_the_evaluation_count_and_nothing_else():
    report = {"status": "ok", "objective": 0.5, "solver": {"method": "auto", "evaluations": 1489}}
    text = json.dumps(report, indent=2)
    other = text.replace("1489", "1449")
    assert masked(text, "json") == masked(other, "json") != text
    assert f'"evaluations": "{MASK}"' in masked(text, "json")
    assert masked(text, "json") != masked(text.replace("0.5", "0.50001"), "json")
    with pytest.raises(AssertionError):  # a count that is not a whole number is not masked away
        masked(text.replace("1489", "1489.5"), "json")
    # the Solver table: its padding follows its widest cell, here the count itself
    assert masked(solver_table(1492565), "table") == masked(solver_table(999999), "table")
    assert masked(solver_table(1492565), "table").splitlines()[5] == f"evaluations   {MASK}"
    assert masked(solver_table(1489, seed="1"), "table") != masked(solver_table(1489), "table")
    assert masked(solver_table(1489), "table").startswith("Error        \nobjective 0.5\n")  # kept


def solver_table(count: int, seed: str = "0") -> str:
    """A report's last two tables as the table view pads them (every line of a table to
    its width)."""
    rows = [("method", "auto"), ("seed", seed), ("evaluations", str(count)), ("converged", "yes")]
    width = max(len(v) for _, v in rows)
    solver = ["Solver".ljust(14 + width)] + [f"{k:<14}{v:<{width}}" for k, v in rows]
    return "\n".join(["Error        ", "objective 0.5", *solver, ""])
