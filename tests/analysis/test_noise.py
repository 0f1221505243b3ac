"""The noise floor, the tie rule and numbers in messages (linkcli.noise, linkcli.textnum),
each against a plain reference written here."""

from __future__ import annotations

import math
import re

import numpy as np
from conftest import ROOT
from hypothesis import given
from hypothesis import strategies as st

from linkcli.noise import NOISE_FLOOR, TIE, first_max, first_min, same, snap, snap_series
from linkcli.textnum import num, render

finite = st.floats(-1e12, 1e12, allow_nan=False)
scales = st.floats(1e-6, 1e6)


@given(finite, scales)
def test_snap_zeroes_exactly_what_is_within_the_floor(value, scale):
    expected = 0.0 if abs(value) <= 1e-9 * scale else value
    got = snap(value, scale)
    assert got == expected and math.copysign(1.0, got) == math.copysign(1.0, expected + 0.0)


def test_snap_keeps_shapes_and_passes_non_finite_values():
    out = snap(np.array([1e-12, -1e-12, 1.0, np.inf, np.nan]), 1.0)
    assert out.tolist()[:4] == [0.0, 0.0, 1.0, math.inf] and math.isnan(out[4])
    assert math.copysign(1.0, snap(-1e-20, 1.0)) == 1.0  # no -0.0


def test_a_series_of_round_off_snaps_against_its_natural_scale():
    at_rest = np.array([3e-17, -2e-16, 0.0])
    assert snap_series(at_rest, natural_scale=1.0).tolist() == [0.0, 0.0, 0.0]
    moving = np.array([2.5, -1e-12, 1e-3])
    assert snap_series(moving).tolist() == [2.5, 0.0, 1e-3]


@given(st.lists(st.floats(-1e6, 1e6), min_size=1, max_size=30))
def test_first_max_is_the_first_of_the_values_within_the_tie_of_the_largest(values):
    top = max(values)
    ref = next(i for i, v in enumerate(values) if abs(v - top) <= 1e-9 * abs(top) or v == top)
    assert first_max(values) == ref
    low = min(values)
    ref_min = next(i for i, v in enumerate(values) if abs(v - low) <= 1e-9 * abs(low) or v == low)
    assert first_min(values) == ref_min


def test_equal_peaks_that_differ_by_round_off_go_to_the_first_in_order():
    push_first = [34761.70000000001, 34761.7]
    pull_first = [34761.7, 34761.70000000001]
    assert first_max(push_first) == 0 and first_max(pull_first) == 0
    assert first_max([1.0, 1.0 + 2e-9]) == 1  # beyond the tie: the larger wins
    assert same(1.0, 1.0 + 0.5e-9) and not same(1.0, 1.0 + 2e-9) and same(math.inf, math.inf)


def test_docs_state_the_constants_the_code_uses():
    """docs/determinism.md ("Noise floor", "Ties") states both constants: they are what it says."""
    text = (ROOT / "docs" / "determinism.md").read_text(encoding="utf-8")
    floor = re.search(r"`NOISE_FLOOR = ([0-9.e+-]+)`", text)
    tie = re.search(r"`TIE = ([0-9.e+-]+)`", text)
    assert floor and tie
    assert float(floor.group(1)) == NOISE_FLOOR == 1e-9 and float(tie.group(1)) == TIE == 1e-9


def test_first_max_along_rows_and_never_nan():
    table = np.array([[1.0, np.nan, 1.0], [np.nan, 2.0, 3.0]])
    assert first_max(table, axis=1).tolist() == [0, 2]


@given(st.floats(allow_nan=False, allow_infinity=False), st.integers(1, 17))
def test_numbers_in_text_follow_the_precision(value, digits):
    text = f"mu falls to {num(value)} deg; again {num(value)}"
    shown = f"{value:.{digits}g}"
    shown = "0" if float(shown) == 0.0 else shown
    assert render(text, digits) == f"mu falls to {shown} deg; again {shown}"
    assert render("; ".join([text, "plain"]), digits).endswith("; plain")
