"""Hostile input, fourth round (issue 47), bounded work on accepted input: every accepted file
runs in bounded memory, in time proportional to its work, and what cannot be bounded is
refused with exit 2 naming the limit.

Memory is asserted (a peak resident size, measured in the process that did the work), time
never is: a guard against unbounded growth, not a speed test."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from conftest import ROOT, run_cli

SRC = str(ROOT / "src")
ENV = dict(os.environ, PYTHONPATH=SRC)
FOUR_BAR = ('type = "linkage"\n[linkage]\nground = 50\ninput = 27.6293\ncoupler = 57.2363\noutput = 41.1104\n'
            'branch = "open"\n[motion]\ninput_speed = 20\nsteps = 36\n[report]\nsections = ["lengths", "tolerance"]\n'
            '[tolerance]\nlengths = {lengths}\nclearance = 0.02\nsamples = {samples}\nallowed_error = 0.5\n'
            'max_failure_probability = 0.01\n[solver]\nseed = 1\n')


def peak_rss_mb(path: str) -> tuple[float, dict]:
    """(peak resident size in MB, report) of `run(path)` in a fresh Python process."""
    code = ("import json, resource, sys\n"
            "from linkcli.pipeline import Request, run\n"
            f"outcome = run({path!r}, Request())\n"
            "json.dump({'rss': resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, "
            "'tolerance': outcome.result.report['tolerance']}, sys.stdout)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=ENV, cwd=ROOT,
                          timeout=600)
    assert done.returncode == 0, done.stderr
    data = json.loads(done.stdout)
    return data["rss"] / 1024.0, data["tolerance"]


def test_the_inverse_mode_keeps_memory_bounded_whatever_samples_x_targets(tmp_path):
    """A given tolerance 27 times the answer leaves every sample undecided: keeping their
    draws for the bisection (samples x 36 targets x 4 pins) peaked at 2.4 GB for 200,000
    samples (5.75 to 12 GB at 1,000,000). Now the bracket is halved by full passes until the
    undecided samples fit in inverse_search.KEEP_UNDECIDED (256 MB): under 500 MB here."""
    path = tmp_path / "inverse.toml"
    path.write_text(FOUR_BAR.replace("{lengths}", "1.0").replace("{samples}", "200000"))
    peak, tol = peak_rss_mb(str(path))
    print(f"peak {peak:.0f} MB, largest tolerance {tol['largest_tolerance']}")
    assert peak < 500
    assert 0.03 < tol["largest_tolerance"] < 0.04
    assert tol["failure_probability_at_largest"] <= 0.01


def test_the_inverse_mode_gives_the_same_answer_within_any_memory_budget(monkeypatch, tmp_path):
    """The bounded search takes the same bisection steps as the one that keeps every
    undecided sample: a budget of a few samples' draws gives the same report, bit for bit,
    and holds no more than the budget."""
    from linkcli.analysis import inverse_search
    from linkcli.pipeline import Request, run
    path = tmp_path / "inverse.toml"
    path.write_text(FOUR_BAR.replace("{lengths}", "0.2").replace("{samples}", "20000"))
    wide = run(str(path), Request()).result.report["tolerance"]
    held = []
    full = inverse_search.Search.full

    def watched(self, ts, keep=None):
        out, kept = full(self, ts, keep)
        held.append(0 if kept is None else sum(len(index) for index, _ in kept) * self.per_sample)
        return out, kept

    monkeypatch.setattr(inverse_search.Search, "full", watched)
    monkeypatch.setattr(inverse_search, "KEEP_UNDECIDED", 20_000)
    monkeypatch.setattr(inverse_search.Search.__init__, "__defaults__", (20_000,))
    narrow = run(str(path), Request()).result.report["tolerance"]
    assert narrow == wide
    assert max(held) <= 20_000 and len(held) > 3  # full passes halved the bracket
