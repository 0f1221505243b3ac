"""Increments (linkcli.search.increments): the chain solve, J^T r, diag(J^T J), the damped
solve and product against the dense matrices assembled here and numpy.linalg; the path
field's Jacobians in these factors against the dense ones (path_generation.search); and a
Levenberg-Marquardt step with the sweep's plane against the dense step."""

from __future__ import annotations

import numpy as np
import pytest

from linkcli.search.increments import Increments, chain_solve


def test_chain_solve_matches_the_dense_system():
    rng = np.random.default_rng(0)
    rows, n = 3, 17
    c = rng.uniform(0, 2, (rows, n))
    k = rng.choice([-1.0, 0.0, 1.0], (rows, n))  # 0: a held unknown
    dt = rng.uniform(0.1, 1.0, (rows, n))
    z = rng.normal(size=(rows, n, 4))
    y = chain_solve(c, k, dt, z)
    t = np.tril(np.ones((n, n)))
    for i in range(rows):
        m = np.diag(k[i]) @ t.T @ np.diag(c[i]) @ t @ np.diag(k[i]) + np.diag(dt[i])
        np.testing.assert_allclose(y[i], np.linalg.solve(m, z[i]), rtol=1e-10, atol=1e-12)


def random_increments(rng, rows=3, p=3, n=11, r=5):
    owner = np.concatenate([np.repeat(np.arange(n), 3), np.full(4, -1)])
    owner = owner[rng.permutation(len(owner))]
    m = len(owner)
    w = rng.normal(size=(rows, m, p))
    local = np.where(owner >= 0, rng.normal(size=(rows, m)), 0.0)
    f, h = rng.normal(size=(rows, m, r)), rng.normal(size=(rows, r, n))
    e = np.ones((rows, n))
    e[:, 1:] = rng.choice([-1.0, 1.0], rows)[:, None]
    dense = np.zeros((rows, m, p + n))
    for i in range(rows):
        lm = np.zeros((m, n))
        own = owner >= 0
        lm[np.flatnonzero(own), owner[own]] = local[i, own]
        dense[i] = np.concatenate([w[i], (lm + f[i] @ h[i]) @ (np.tril(np.ones((n, n))) * e[i][None, :])], axis=1)
    return Increments(w, local, owner, f, h, e), dense


def test_normal_equations_match_the_dense_ones():
    rng = np.random.default_rng(1)
    jac, dense = random_increments(rng)
    rows, m, k = dense.shape
    r = rng.normal(size=(rows, m))
    np.testing.assert_allclose(jac.gradient(r), np.einsum("nmk,nm->nk", dense, r), rtol=1e-12, atol=1e-12)
    keep = rng.random((rows, k)) > 0.2
    damp = rng.uniform(0.1, 1.0, (rows, k))
    y = rng.normal(size=(rows, k, 2))
    normal = jac.normal(keep)
    x = normal.solve(damp, y)
    for i in range(rows):
        h = dense[i].T @ dense[i] * np.outer(keep[i], keep[i])
        np.testing.assert_allclose(normal.diagonal()[i], np.diag(h), rtol=1e-10, atol=1e-10)
        np.testing.assert_allclose(normal.matvec(damp, y[..., 0])[i], (h + np.diag(damp[i])) @ y[i, :, 0],
                                   rtol=1e-10, atol=1e-10)
        np.testing.assert_allclose(x[i], np.linalg.solve(h + np.diag(damp[i]), y[i]), rtol=1e-8, atol=1e-10)


def test_an_angle_without_rows_is_refused():
    with pytest.raises(ValueError):
        Increments(np.zeros((1, 2, 1)), np.zeros((1, 2)), np.array([0, 2]), np.zeros((1, 2, 1)),
                   np.zeros((1, 1, 3)), np.ones((1, 3)))


def field_of(constraints: str, seed: int):
    """Rows of the path field for a free-timing problem of 44 targets on a crank-rocker's
    coupler curve, some with their lengths scaled so that penalties bind."""
    from linkcli.reading.load import load
    from linkcli.search.budget import Budget
    from linkcli.types.path_generation import starts
    from linkcli.types.path_generation.model import build
    from linkcli.types.path_generation.search import Space
    rng = np.random.default_rng(seed)
    phi = np.linspace(0.1, 5.5, 44)
    a, b, c, d = 1.2, 3.6, 2.9, 4.0
    ax, ay = a * np.cos(phi), a * np.sin(phi)
    v = ax - d + 1j * ay
    alpha = np.arccos((abs(v) ** 2 + c * c - b * b) / (2 * abs(v) * c))
    bb = d + c * np.exp(1j * (np.angle(v) - alpha))
    pts = ax + 1j * ay + (1.5 + 1.1j) * np.exp(1j * np.angle(bb - ax - 1j * ay))
    text = ('type = "path-generation"\n[target]\npoints = [%s]\ntiming = "free"\n[bounds]\nground = [0.5, 10]\n'
            'input = [0.2, 5]\ncoupler = [0.5, 10]\noutput = [0.5, 10]\ncoupler_point = { x = [-10, 10], '
            'y = [-10, 10] }\nground_pivot = { x = [-10, 10], y = [-10, 10] }\nground_angle = [-180, 180]\n'
            % ", ".join(f"[{float(p.real)!r}, {float(p.imag)!r}]" for p in pts)) + constraints
    design = build(load("x.toml", text))
    x, sign, s = starts.starts(design, rng, 60)
    space = Space(design, Budget(10**9), project=True)
    z = space.free(x)[:8].copy()
    z[2:, :4] *= rng.uniform(0.9, 1.1, (6, 4))  # lengths off: windows and Grashof rows broken
    return space, z, sign[:8], s[:8]


@pytest.mark.parametrize("constraints,seed", [('[constraints]\ngrashof = "any"\ntransmission = [70, 110]\n', 1),
                                              ('[constraints]\ngrashof = "crank-rocker"\ntransmission = [80, 100]\n', 1),
                                              ('[constraints]\ngrashof = "double-rocker"\n', 3),
                                              ('[constraints]\ngrashof = "triple-rocker"\n', 3)])
def test_path_field_jacobian_in_factors_equals_the_dense_one(constraints, seed):
    """Every row whose closed form holds: target errors and penalties (Grashof rows, a
    window over the span or the full turn, assembly, the sweep) the same to round-off."""
    from linkcli.types.path_generation import derivatives
    space, z, sign, s = field_of(constraints, seed)
    assert space.increments
    r0 = space.residuals(z, sign, s, 1e2)
    jac = space.jacobian(z, sign, s, 1e2, r0)
    space.increments = False
    dense = space.jacobian(z, sign, s, 1e2, r0)
    n = jac.n
    rows, m, _ = dense.shape
    lm = np.zeros((rows, m, n))
    own = np.flatnonzero(jac.owner >= 0)
    lm[:, own, jac.owner[own]] = jac.local[:, own]
    e = np.stack([np.tril(np.ones((n, n))) * jac.e[i][None, :] for i in range(rows)])
    full = np.concatenate([jac.w, np.einsum("nmk,nkj->nmj", lm + np.einsum("nmr,nrk->nmk", jac.f, jac.h), e)],
                          axis=2)
    x, frame = space.fitted(z, sign, s)
    _, ok = derivatives.projected_jacobian(space.design, space.idx, x, frame, sign, s)
    assert ok.sum() >= 3 and np.any(r0[ok][:, 2 * n:] > 0)  # penalties bind on rows checked
    for i in np.flatnonzero(ok):
        np.testing.assert_allclose(full[i], dense[i], rtol=0, atol=1e-12 * max(1.0, np.abs(dense[i]).max()))
    # where the closed form fails the dense rows come from differences: the penalties'
    # slopes (assembly broken there) agree with them to the differences' accuracy
    bad = np.flatnonzero(~ok)
    assert len(bad) and np.any(r0[bad][:, 2 * n:] > 0)
    for i in bad:
        np.testing.assert_allclose(full[i, 2 * n:], dense[i, 2 * n:], rtol=0,
                                   atol=1e-6 * max(1.0, np.abs(dense[i, 2 * n:]).max()))


def test_a_step_with_the_sweeps_plane_equals_the_dense_step():
    """One Levenberg-Marquardt step from rows whose sweep would cross 2 pi: the step held
    on the plane (and at the bounds it meets) is the dense step's, to round-off."""
    from linkcli.search import levenberg_marquardt as lm
    space, z, sign, s = field_of('[constraints]\ngrashof = "crank-rocker"\n', 2)
    k = z.shape[1]
    timing = space.idx >= 10
    z[:, timing] = np.clip(z[:, timing] * 1.3, space.lo[timing], space.hi[timing])  # sweeps near a turn
    r0 = space.residuals(z, sign, s, 1e2)
    jac = space.jacobian(z, sign, s, 1e2, r0)
    lam = np.full(len(z), 1e-2)
    got = lm._structured_step(jac, r0, z, lam, space.lo, space.hi, space.linear)
    space.increments = False
    j = space.jacobian(z, sign, s, 1e2, r0)
    g = np.einsum("nmk,nm->nk", j, r0)
    frozen = lm._frozen(z, g, space.lo, space.hi)
    keep = ~frozen
    h = np.einsum("nmk,nml->nkl", j, j) * keep[:, :, None] * keep[:, None, :]
    a = h + np.einsum("nk,kl->nkl", lm._damping(np.einsum("nkk->nk", h), lam, frozen), np.eye(k))
    both = np.stack([np.linalg.solve(a[i], np.stack([g[i] * keep[i], space.linear[0] * keep[i]], axis=1))
                     for i in range(len(z))])
    step = -both[..., 0] * keep
    want = lm._on_plane(space.linear, lm.Dense(a), g * keep, both[..., 1], z, step, keep, space.lo, space.hi)
    from linkcli.types.path_generation import derivatives
    x, frame = space.fitted(z, sign, s)
    ok = derivatives.projected_jacobian(space.design, space.idx, x, frame, sign, s)[1]  # (else: differences)
    on = np.einsum("nk,k->n", z + want, space.linear[0]) >= space.linear[1] - 1e-9
    assert np.any(ok & on)  # the plane binds on a row compared
    np.testing.assert_allclose(got[ok], want[ok], rtol=1e-7, atol=1e-10)
