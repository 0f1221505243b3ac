"""Top-level item functions for tests/cli/test_cluster.py (Dask workers import them by name).

An item is `(name, seed)` or `(name, seed, options)`; each function returns what the CLI's
run_one returns, `(exit code, report or None, error lines)`, and reports bad input in its
result instead of raising.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np

from linkcli.mechanisms.four_bar.kinematics import grashof_code, pose

SAMPLES = 361  # input angles over one turn


def fake_solve(item):
    """A deterministic stand-in for a solve: a random four-bar from the item's seed,
    posed over a turn of the crank (numpy, vectorized). A negative seed is bad input."""
    name, seed = item[0], item[1]
    if seed < 0:
        return 2, None, [f"{name}: solver.seed: expected an integer >= 0, found {seed}"]
    lengths = np.random.default_rng(seed).uniform(0.5, 2.0, size=4)
    phi = np.linspace(0.0, 2.0 * np.pi, SAMPLES)
    linkage = pose(*lengths, phi)
    psi = linkage.psi[linkage.valid]
    report = {"file": name, "lengths": lengths.tolist(),
              "grashof": int(grashof_code(*lengths)),
              "assembles": int(linkage.valid.sum()),
              "output_range": float(psi.max() - psi.min()) if psi.size else None}
    return (0 if psi.size == SAMPLES else 1), report, []


def buggy_solve(item):
    """fake_solve, except that an item named "bug" raises (a bug, not bad input)."""
    if item[0] == "bug":
        raise RuntimeError("index out of range\nsecond line of the message")
    return fake_solve(item)


def logged_solve(item):
    """fake_solve after `options["sleep"]` seconds, appending "name pid" to
    options["log"] as it starts; the item named options["die_once"] ends its worker
    process (os._exit) the first time it runs, and the item named options["wait_for"]
    finishes only after the item named options["release"] has (or after 60 s)."""
    name, seed, options = item
    folder = Path(options["folder"])
    with open(folder / "starts.log", "a") as log:
        log.write(f"{name} {os.getpid()}\n")
    if name == options.get("die_once"):
        try:
            os.close(os.open(folder / "died", os.O_CREAT | os.O_EXCL))
            os._exit(1)
        except FileExistsError:
            pass  # the rerun after the worker's death
    if name == options.get("wait_for_release"):
        deadline = time.monotonic() + 60.0
        while not (folder / "released").exists() and time.monotonic() < deadline:
            time.sleep(0.02)
    time.sleep(options.get("sleep", 0.0))
    result = fake_solve((name, seed))
    if name == options.get("release"):
        (folder / "released").touch()
    return result


def always_crash(item):
    """fake_solve, except that an item named "crash" ends its worker process every time."""
    if item[0] == "crash":
        os._exit(1)
    return fake_solve(item)


def sleep_pid(item):
    """Sleep `item[1]` seconds, then return the worker's process id."""
    time.sleep(item[1])
    return os.getpid()
