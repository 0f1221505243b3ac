"""The path search's closed-form Jacobians against fine differences of an independent model.

The reference is written here from the conventions of docs/format.md with numpy's complex
numbers, not taken from linkcli: the loop closure at each target, the coupler point, and
for the projected residuals the coupler point and ground pivot solved by numpy's own least
squares (`numpy.linalg.lstsq`). Slopes by central differences with Richardson
extrapolation (steps h and h/2), on draws of the bench problems (free and prescribed
timing, fixed and free pivots, free offsets).
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import ROOT

PROBLEMS = ["kunjur5", "lin10_closed", "closed18_timed", "cabrera6_line", "arc6_window"]


def design_of(name: str):
    from linkcli.io.safe_read import read_problem_bytes
    from linkcli.reading.load import load
    from linkcli.types.path_generation.model import build

    path = str(ROOT / "problems" / "bench" / f"{name}.toml")
    return build(load(path, read_problem_bytes(path)))


def input_angles(design, x, s):
    if design.timing == "prescribed":
        return design.base_phi + x[9]
    return x[9] + s * np.concatenate([[0.0], np.cumsum(x[10:])])


def local_points(design, x, sign, s):
    """Coupler points in the ground frame before the pivot (complex, per target), and
    the crank pin and coupler direction they are built from."""
    d, a, b, c = x[:4]
    phi = input_angles(design, x, s)
    A = a * np.exp(1j * phi)
    v = A - d
    rho = np.abs(v)
    alpha = np.arccos(np.clip((rho * rho + c * c - b * b) / (2 * rho * c), -1.0, 1.0))
    psi = np.angle(v) + sign * alpha
    B = d + c * np.exp(1j * psi)
    e = np.exp(1j * np.angle(B - A))
    return A, e


def errors(design, x, sign, s):
    """(2n,) target errors / L, every variable given."""
    A, e = local_points(design, x, sign, s)
    P = complex(x[6], x[7]) + np.exp(1j * x[8]) * (A + complex(x[4], x[5]) * e)
    r = (P - (design.targets[:, 0] + 1j * design.targets[:, 1])) / design.scale
    return np.stack([r.real, r.imag], axis=1).ravel()


def projected_errors(design, x, sign, s):
    """(2n,) target errors / L with the free coordinates of the coupler point and the
    pivot solved by unconstrained linear least squares, and that solution."""
    A, e = local_points(design, x, sign, s)
    w = np.exp(1j * x[8])
    cols = [w * e, 1j * w * e, np.ones_like(e), np.full_like(e, 1j)]
    t = design.targets[:, 0] + 1j * design.targets[:, 1] - w * A
    free = [j for j in range(4) if design.free[4 + j]]
    for j in range(4):
        if j not in free:
            t = t - cols[j] * design.lo[4 + j]
    m = np.array([np.concatenate([cols[j].real, cols[j].imag]) for j in free]).T
    y = np.linalg.lstsq(m, np.concatenate([t.real, t.imag]), rcond=None)[0] if free else np.zeros(0)
    full = x.copy()
    full[[4 + j for j in free]] = y
    return errors(design, full, sign, s), full


def richardson(f, z, j, h):
    """d f / d z_j by central differences at h and h/2, extrapolated."""
    def central(step):
        up, down = z.copy(), z.copy()
        up[j] += step
        down[j] -= step
        return (f(up) - f(down)) / (2 * step)
    return (4 * central(h / 2) - central(h)) / 3


def draws(design, n=12, seed=0):
    from linkcli.types.path_generation import starts
    return starts.starts(design, np.random.default_rng(seed), n)


@pytest.mark.parametrize("name", PROBLEMS)
def test_projected_jacobian_matches_fine_differences(name):
    from linkcli.search.budget import Budget
    from linkcli.types.path_generation.search import Space

    design = design_of(name)
    x, sign, s = draws(design)
    space = Space(design, Budget(10**9), project=True)
    z = space.free(x)
    r0 = space.residuals(z, sign, s, 0.0)
    jac = space.jacobian(z, sign, s, 0.0, r0)
    checked = 0
    for i in range(len(z)):
        ref_x = space.full(z[i:i + 1])[0]
        _, solved = projected_errors(design, ref_x, sign[i], s[i])
        lin = [j for j in range(4, 8) if design.free[j]]
        if np.any(solved[lin] <= design.lo[lin]) or np.any(solved[lin] >= design.hi[lin]):
            continue  # a bound holds the fit: another function than the unconstrained one

        def f(zi, i=i):
            xi = space.full(zi[None])[0]
            return projected_errors(design, xi, sign[i], s[i])[0]

        ref = np.stack([richardson(f, z[i], j, 1e-5 * max(abs(z[i, j]), 1e-3)) for j in range(space.k)], axis=1)
        assert np.max(np.abs(jac[i] - ref)) <= 1e-6 * np.max(np.abs(ref)), (name, i)
        checked += 1
    assert checked >= len(z) // 4


@pytest.mark.parametrize("name", PROBLEMS)
def test_jacobian_on_every_variable_matches_fine_differences(name):
    from linkcli.search.budget import Budget
    from linkcli.types.path_generation.search import Space

    design = design_of(name)
    x, sign, s = draws(design, seed=1)
    space = Space(design, Budget(10**9))
    z = space.free(x)
    r0 = space.residuals(z, sign, s, 0.0)
    jac = space.jacobian(z, sign, s, 0.0, r0)
    for i in range(len(z)):
        def f(zi, i=i):
            return errors(design, space.full(zi[None])[0], sign[i], s[i])

        ref = np.stack([richardson(f, z[i], j, 1e-5 * max(abs(z[i, j]), 1e-3)) for j in range(space.k)], axis=1)
        assert np.max(np.abs(jac[i] - ref)) <= 1e-6 * np.max(np.abs(ref)), (name, i)


def test_a_variable_within_round_off_of_its_bound_gets_a_faithful_slope():
    """A draw of cabrera6_line had its output length 7e-15 below the upper bound: the
    difference step shrunk to that room gave slopes wrong in the first digit. Now it
    steps away from the bound (one-sided, second order)."""
    from linkcli.search.budget import Budget
    from linkcli.types.path_generation.search import Space

    design = design_of("cabrera6_line")
    x, sign, s = draws(design, n=4)
    design.hi = design.hi.copy()
    design.hi[3] = x[0, 3] * (1 + 2.0 ** -52)  # the output length within round-off of its bound
    space = Space(design, Budget(10**9))
    z = space.free(x[:1])
    r0 = space.residuals(z, sign[:1], s[:1], 0.0)
    diff = space._differences(z, r0, space._shifted(sign[:1], s[:1], 0.0), 2 * design.n_targets)
    col = list(space.idx).index(3)

    def f(zi):
        return errors(design, space.full(zi[None])[0], sign[0], s[0])

    h = 1e-5 * z[0, col]
    down1, down2 = z[0].copy(), z[0].copy()
    down1[col] -= h
    down2[col] -= 2 * h
    ref = (3 * f(z[0]) - 4 * f(down1) + f(down2)) / (2 * h)  # backward, second order
    assert np.max(np.abs(ref)) > 1e-3
    assert np.max(np.abs(diff[0, :, col] - ref)) <= 1e-4 * np.max(np.abs(ref))


def test_solve_spd_with_several_right_hand_sides_matches_lapack():
    from linkcli.search import linalg

    rng = np.random.default_rng(3)
    m = rng.normal(size=(5, 4, 4))
    a = m @ np.transpose(m, (0, 2, 1)) + 4 * np.eye(4)
    b = rng.normal(size=(5, 4, 3))
    assert np.allclose(linalg.solve_spd(a, b), np.linalg.solve(a, b), rtol=1e-12, atol=1e-12)
    assert np.allclose(linalg.solve_spd(a, b[:, :, 0]), np.linalg.solve(a, b[:, :, :1])[:, :, 0],
                       rtol=1e-12, atol=1e-12)


# ---------------------------------------------------------------- penalties

SHORTEST = {"crank-rocker": 1, "double-crank": 0, "rocker-crank": 3, "double-rocker": 2}
CONSTRAINED = {
    "double-rocker, window over the span, prescribed": ("double-rocker", "[30, 150]", "prescribed"),
    "crank-rocker, window over the turn, free": ("crank-rocker", "[40, 140]", "free"),
    "triple-rocker, window, prescribed": ("triple-rocker", "[20, 160]", "prescribed"),
    "rocker-crank, free": ("rocker-crank", None, "free"),
}


def constrained_design(tmp_path, grashof, window, timing):
    from linkcli.io.safe_read import read_problem_bytes
    from linkcli.reading.load import load
    from linkcli.types.path_generation.model import build

    target = ('timing = "prescribed"\ninput_angles = [20, 50, 80, 110, 140]' if timing == "prescribed"
              else 'timing = "free"')
    text = f"""type = "path-generation"
[target]
points = [[0, 0], [3, 1], [5, 3], [6, 6], [5, 8]]
{target}
[bounds]
ground = [1, 20]
input = [1, 20]
coupler = [1, 20]
output = [1, 20]
coupler_point = {{ x = [-20, 20], y = [-20, 20] }}
ground_pivot = {{ x = [-20, 20], y = [-20, 20] }}
ground_angle = [0, 360]
{"input_offset = [-180, 180]" if timing == "prescribed" else ""}
[constraints]
grashof = "{grashof}"
{f"transmission = {window}" if window else ""}
"""
    path = tmp_path / "p.toml"
    path.write_text(text, encoding="utf-8")
    return build(load(str(path), read_problem_bytes(str(path))))


def constraint_values(design, x, s):
    """The constraint functions g (g <= 0 holds) of one candidate, written from their
    definitions: the Grashof class (the class's shortest link s: s + x_j - the other two
    + margin for each other link; triple-rocker p + q - s - l + margin), the
    transmission window at the extremes of rho = |A B0| (over the full turn for a
    crank-rocker or double-crank, else over the targets' span), assembly at each target,
    the dead points phi = 0, pi inside the span, and for free timing the sweep."""
    from linkcli.types.path_generation.model import GRASHOF_MARGIN

    d, a, b, c = x[:4]
    links = [d, a, b, c]
    margin = GRASHOF_MARGIN * sum(links)
    g = []
    if design.grashof in SHORTEST:
        k = SHORTEST[design.grashof]
        others = [j for j in range(4) if j != k]
        for j in others:
            rest = [links[o] for o in others if o != j]
            g.append(links[k] + links[j] - rest[0] - rest[1] + margin)
    elif design.grashof == "triple-rocker":
        srt = sorted(links)
        g.append(srt[1] + srt[2] - srt[0] - srt[3] + margin)
    phi = input_angles(design, x, s)
    lo, hi = phi.min(), phi.max()

    def within(angle):
        return (angle - lo) % (2 * np.pi) <= hi - lo

    def r2(angle):
        return a * a + d * d - 2 * a * d * np.cos(angle)

    if design.window is not None:
        if design.full_turn:
            r2_min, r2_max = (d - a) ** 2, (d + a) ** 2
        else:
            r2_min = (a - d) ** 2 if within(0.0) else min(r2(lo), r2(hi))
            r2_max = (a + d) ** 2 if within(np.pi) else max(r2(lo), r2(hi))
        cos_mu = lambda v: (b * b + c * c - v) / (2 * b * c)  # noqa: E731
        g.append(design.scale * (cos_mu(r2_min) - np.cos(design.window[0])))
        g.append(design.scale * (np.cos(design.window[1]) - cos_mu(r2_max)))
    for angle in phi:
        rho = abs(a * np.exp(1j * angle) - d)
        g.append(max(abs(b - c) - rho, rho - (b + c)))
    for angle, rho in ((0.0, abs(a - d)), (np.pi, a + d)):
        v = max(abs(b - c) - rho, rho - (b + c))
        g.append(v if within(angle) else min(v, 0.0))
    if design.timing == "free":
        g.append(design.scale * (sum(x[10:]) - 2 * np.pi))
    return np.array(g)


@pytest.mark.parametrize("case", sorted(CONSTRAINED))
def test_penalty_slopes_match_fine_differences_where_violated(tmp_path, case):
    from linkcli.search.budget import Budget
    from linkcli.types.path_generation import derivatives
    from linkcli.types.path_generation.search import Space

    design = constrained_design(tmp_path, *CONSTRAINED[case])
    rng = np.random.default_rng(5)
    x, sign, s = draws(design, n=40, seed=2)
    x[:, :4] = design.lo[:4] + rng.random((40, 4)) * (design.hi[:4] - design.lo[:4])  # break the class
    if design.timing == "free":
        x[:, 10:] = rng.random((40, x.shape[1] - 10)) * 1.5  # some beyond one turn
    weight = 100.0
    space = Space(design, Budget(10**9), project=True)
    z = space.free(x)
    full = space.full(z)
    frame, _ = design.frame(full, sign, s)
    violated = np.array([constraint_values(design, row, si) > 0 for row, si in zip(full, s)])
    jac = derivatives.penalty_jacobian(design, space.idx, full, frame, s, weight, violated)
    checked = 0
    for i in range(len(z)):
        def f(zi, i=i):
            return weight * np.maximum(constraint_values(design, space.full(zi[None])[0], s[i]), 0.0) / design.scale

        for j in range(space.k):
            h = 1e-5 * max(abs(z[i, j]), 1e-2)
            points = [z[i].copy() for _ in range(5)]
            for p, t in zip(points, (-1.0, -0.5, 0.0, 0.5, 1.0)):
                p[j] += t * h
            values = np.array([f(p) for p in points])
            active = np.all(values > 0, axis=0)  # violated all along: one smooth piece
            inactive = np.all(values == 0, axis=0)
            ref = (4 * (values[3] - values[1]) / h - (values[4] - values[0]) / (2 * h)) / 3
            scale = np.maximum(np.abs(ref), 1e-3 * weight)
            assert np.all(np.abs(jac[i, active, j] - ref[active]) <= 1e-6 * scale[active]), (case, i, j)
            assert np.all(jac[i, inactive, j] == 0.0)
            checked += int(active.sum())
    assert checked > 50
