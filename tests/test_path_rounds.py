"""The path multistart's rounds: the first two run side by side without exchanging rows,
an exact fit settles the search in one round, and the Jacobians reuse the residual call's
fit only at the very points it was made for."""

from __future__ import annotations

import numpy as np

from conftest import ROOT


def design_of(name: str):
    from linkcli.io.load import load
    from linkcli.io.safe_read import read_problem_bytes
    from linkcli.types.path_generation.model import build

    path = str(ROOT / "problems" / "bench" / f"{name}.toml")
    return build(load(path, read_problem_bytes(path)))


def test_rounds_side_by_side_end_as_each_alone():
    """The first round of a pair ends where it ends alone (same draws: the rng gives the
    second round's draws after the first's): the batched steps never mix the rounds."""
    from linkcli.search.budget import Budget
    from linkcli.types.path_generation.solve import one_round

    design = design_of("kunjur5")
    pair = one_round(design, Budget(10**7), np.random.default_rng(3), [100_000, 100_000])
    alone = one_round(design, Budget(10**7), np.random.default_rng(3), [100_000])
    assert len(pair) == 2 and len(alone) == 1
    assert len(pair[0]) == len(alone[0])
    for a, b in zip(pair[0], alone[0]):
        assert np.allclose(a.x, b.x, rtol=1e-12, atol=1e-12) and a.sign == b.sign
    # and the second round is another search: its own draws, its own end points
    assert not all(np.allclose(a.x, b.x) for a, b in zip(pair[1], pair[0]))


def test_an_exact_fit_in_the_field_settles_the_search_without_a_second_draw(monkeypatch):
    """closed_curve12's targets lie on a four-bar's coupler curve: the first field round
    fits them exactly, so the second round of the pair is never drawn; kunjur5 has no
    exact fit, so both are."""
    from linkcli.search.budget import Budget
    from linkcli.types.path_generation import solve as path_solve
    from linkcli.types.path_generation import starts

    calls = []
    original = starts.starts

    def counted(*args, **kwargs):
        calls.append(args[2])
        return original(*args, **kwargs)

    monkeypatch.setattr(starts, "starts", counted)
    for name, draws in (("closed_curve12", 1), ("kunjur5", 2)):
        calls.clear()
        design = design_of(name)
        cands, confirmed = path_solve.multistart(design, Budget(2_000_000), np.random.default_rng(0))
        assert len(calls) == draws, name
        assert confirmed


def test_jacobians_reuse_the_fit_only_of_the_points_just_evaluated():
    from linkcli.search.budget import Budget
    from linkcli.types.path_generation import starts
    from linkcli.types.path_generation.search import Fixed, Space

    for name in ("lin10_closed", "arc6_window"):
        design = design_of(name)
        x, sign, s = starts.plain_starts(design, np.random.default_rng(1), 12)
        for project in (True, False):
            space = Space(design, Budget(10**9), project=project)
            fixed = Fixed(space, sign, s, 100.0)
            z = space.free(x)
            r = fixed.residuals(z, np.arange(len(z)))
            sub = np.array([1, 4, 5, 9])
            assert fixed._kept(z[sub], sub) is not None
            kept = fixed.jacobian(z[sub], sub, r[sub])
            fresh = space.jacobian(z[sub], sign[sub], s[sub], 100.0, r[sub])
            assert np.array_equal(kept, fresh, equal_nan=True)
            moved = z.copy()
            moved[sub, 0] = np.minimum(moved[sub, 0] * 1.01, space.hi[0])
            assert fixed._kept(moved[sub], sub) is None  # other points: fitted again
            assert fixed._kept(z[sub], sub + 1) is None  # other rows (their signs)
