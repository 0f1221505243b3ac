"""Arrow Jacobians whose trailing unknowns are increments: free timing's first angle and
its steps from target to target, solved in O(n) a step (numpy, no BLAS).

With free timing each target's input angle phi_k = v_0 + s (v_1 + ... + v_k) is a running
sum of the unknowns v (the first angle, then the steps, s = +-1 the turning direction):
phi = E v, E lower triangular. In phi a target's angle moves its own rows alone (an arrow,
linkcli.search.arrow), but the Levenberg-Marquardt works on v (the steps carry the order's
bounds v_k >= 0), where J E is dense. Kept as its factors, per batch row:

    J = [ W | (L + F H) E ]   W (m, p) the p leading columns (the linkage),
                              L the rows' own angle slopes (`local` (m,), `owner` (m,)),
                              F H a low-rank part (m, r) x (r, n): the variable projection's
                              -A C (Golub & Pereyra) and the penalty rows that several
                              angles move (a transmission window over the targets' span),

J^T J is a dense p x p block bordered by O(n p) terms, a chain E^T diag(c) E (c the angles'
own sums of squares) and V S V^T, V = E^T [L^T F, H^T] (n x 2r), S = [[0, I], [I, F^T F]].
The damped system is solved by eliminating the chain (`chain_solve`: the Riccati recursion
of a linear-quadratic chain in O(n), by parallel prefix scans, no loop over the targets)
and the leading block (Schur complement), and the low-rank part by the Sherman-Morrison-
Woodbury identity (Golub & Van Loan, Matrix Computations, 4th ed., sec. 2.1.4, 3.2.10).
A variable held at a bound (the Levenberg-Marquardt's frozen ones) drops out exactly: its
column of J is zero (K = 0 in the chain) and its row of the system is the identity.
"""

from __future__ import annotations

import numpy as np

from linkcli.search import linalg


def _suffix_products(m: np.ndarray) -> np.ndarray:
    """Q_k = M_k M_{k+1} ... M_{n-1} for 2 x 2 matrices m (N, n, 2, 2) with entries >= 0,
    by doubling (Hillis & Steele 1986), each product rescaled to its largest entry (the
    Moebius map it stands for is the same)."""
    q = m.copy()
    n = q.shape[1]
    d = 1
    while d < n:
        prod = np.einsum("nkij,nkjl->nkil", q[:, :n - d], q[:, d:], optimize=False)
        q[:, :n - d] = prod / np.maximum(np.max(prod, axis=(2, 3), keepdims=True), 1e-300)
        d *= 2
    return q


def _affine_scan(a: np.ndarray, b: np.ndarray, reverse: bool) -> np.ndarray:
    """x_k = a_k x_{k-1} + b_k from x_{-1} = 0 (or, `reverse`, x_k = a_k x_{k+1} + b_k from
    x_n = 0), a (N, n), b (N, n, R), by doubling; the a_k lie in [0, 1] (no overflow)."""
    a, b = a.copy(), b.copy()
    n = a.shape[1]
    d = 1
    while d < n:
        if reverse:  # combine k with k + d
            b[:, :n - d] = b[:, :n - d] + a[:, :n - d, None] * b[:, d:]
            a[:, :n - d] = a[:, :n - d] * a[:, d:]
        else:  # combine k with k - d
            b[:, d:] = b[:, d:] + a[:, d:, None] * b[:, :n - d]
            a[:, d:] = a[:, d:] * a[:, :n - d]
        d *= 2
    return b


def chain_solve(c: np.ndarray, k: np.ndarray, dt: np.ndarray, z: np.ndarray) -> np.ndarray:
    """y with (K T^T diag(c) T K + diag(dt)) y = z, T[i, j] = 1 for j <= i (the running
    sum), for c >= 0, k, dt > 0 (N, n) and z (N, n, R): y minimizes
    1/2 sum_i c_i u_i^2 + 1/2 sum_j dt_j y_j^2 - z . y with u_i = sum_{j <= i} k_j y_j, a chain
    solved by the backward Riccati recursion (P the cost-to-go's curvature, q its slope)

        S_j = c_j + P_{j+1},  P_j = S_j dt_j / (dt_j + k_j^2 S_j),
        q_j = (dt_j q_{j+1} + k_j S_j z_j) / (dt_j + k_j^2 S_j),
        y_j = (z_j - k_j (q_{j+1} + S_j u_{j-1})) / (dt_j + k_j^2 S_j),  u_j = u_{j-1} + k_j y_j,

    each a composition of Moebius or affine maps: parallel prefix scans, log2(n) steps."""
    n_rows, n = c.shape
    k2 = k * k
    m = np.empty((n_rows, n, 2, 2))  # P_j = (dt P + dt c) / (k^2 P + dt + k^2 c) of P = P_{j+1}
    m[..., 0, 0], m[..., 0, 1] = dt, dt * c
    m[..., 1, 0], m[..., 1, 1] = k2, dt + k2 * c
    q = _suffix_products(m)
    p_next = np.zeros((n_rows, n))  # P_{j+1}, P_n = 0
    p_next[:, :-1] = q[:, 1:, 0, 1] / q[:, 1:, 1, 1]
    s = c + p_next
    den = dt + k2 * s
    a = dt / den
    slope = _affine_scan(a, (k * s / den)[:, :, None] * z, reverse=True)  # q_j
    q_next = np.zeros_like(slope)
    q_next[:, :-1] = slope[:, 1:]
    u = _affine_scan(a, (k / den)[:, :, None] * (z - k[:, :, None] * q_next), reverse=False)
    u_prev = np.zeros_like(u)
    u_prev[:, 1:] = u[:, :-1]
    return (z - k[:, :, None] * (q_next + s[:, :, None] * u_prev)) / den[:, :, None]


def running(e: np.ndarray, v: np.ndarray) -> np.ndarray:
    """E v: sum_{j <= i} e_j v_j over axis 1 of v (N, n, ...)."""
    shape = e.shape + (1,) * (v.ndim - 2)
    return np.cumsum(e.reshape(shape) * v, axis=1)


def running_t(e: np.ndarray, w: np.ndarray) -> np.ndarray:
    """E^T w: e_j sum_{i >= j} w_i over axis 1 of w (N, n, ...)."""
    shape = e.shape + (1,) * (w.ndim - 2)
    return e.reshape(shape) * np.flip(np.cumsum(np.flip(w, axis=1), axis=1), axis=1)


class Increments:
    """The Jacobians (N rows of a batch) of a least-squares problem whose trailing n
    unknowns are increments (module docstring): w (N, m, p), local (N, m), owner (m,),
    f (N, m, r), h (N, r, n), e (N, n) the running sum's factors (1, s, s, ...)."""

    def __init__(self, w, local, owner, f, h, e) -> None:
        self.w, self.local, self.owner, self.f, self.h, self.e = w, local, owner, f, h, e
        self.n = e.shape[1]
        self.order = np.argsort(owner, kind="stable")
        self.starts = np.searchsorted(owner[self.order], np.arange(self.n))
        if self.n and not np.all(np.diff(np.append(self.starts, len(owner))) > 0):
            raise ValueError("every angle needs a row of its own")

    FIELDS = ("w", "local", "f", "h", "e")

    @classmethod
    def empty(cls, size: int, like: Increments) -> Increments:
        parts = [np.zeros((size,) + getattr(like, k).shape[1:]) for k in cls.FIELDS]
        return cls(parts[0], parts[1], like.owner, parts[2], parts[3], parts[4])

    def take(self, rows) -> Increments:
        out = Increments.__new__(Increments)
        out.__dict__.update(self.__dict__)
        for k in self.FIELDS:
            setattr(out, k, getattr(self, k)[rows])
        return out

    def put(self, rows, other: Increments) -> None:
        for k in self.FIELDS:
            getattr(self, k)[rows] = getattr(other, k)

    def _per_angle(self, rows: np.ndarray) -> np.ndarray:
        """Sums over each angle's rows of rows (N, m, ...) -> (N, n, ...)."""
        return np.add.reduceat(rows[:, self.order], self.starts, axis=1)

    def gradient(self, r: np.ndarray) -> np.ndarray:
        """J^T r (N, p + n)."""
        gw = np.einsum("nmp,nm->np", self.w, r, optimize=False)
        fr = np.einsum("nmr,nm->nr", self.f, r, optimize=False)
        phi = self._per_angle(self.local * r) + np.einsum("nrk,nr->nk", self.h, fr, optimize=False)
        return np.concatenate([gw, running_t(self.e, phi)], axis=1)

    def normal(self, keep: np.ndarray) -> IncrementsNormal:
        """J^T J with the unknowns not `keep` (N, p + n) left out (their columns of J zero),
        as J0^T J0 + X S X^T: J0 = [W | L E] (a Gram matrix: positive definite once
        damped) and X = [J0^T F, (H E)^T] (N, p + n, 2r), S = [[0, I], [I, F^T F]]."""
        p = self.w.shape[2]
        kw, kt = keep[:, :p].astype(float), keep[:, p:].astype(float)
        w = self.w * kw[:, None, :]
        wt = np.ascontiguousarray(np.transpose(w, (0, 2, 1)))
        ww = np.einsum("npm,nqm->npq", wt, wt, optimize=False)
        wl = self._per_angle(w * self.local[:, :, None])  # (N, n, p): L^T W
        cross = running_t(self.e, wl) * kt[:, :, None]  # (N, n, p): (W^T L E)^T
        lf = running_t(self.e, self._per_angle(self.local[:, :, None] * self.f)) * kt[:, :, None]
        wf = np.einsum("nmp,nmr->npr", w, self.f, optimize=False)  # W^T F
        he = running_t(self.e, np.transpose(self.h, (0, 2, 1))) * kt[:, :, None]  # (H E)^T
        v = np.concatenate([np.concatenate([wf, np.zeros_like(wf)], axis=2),
                            np.concatenate([lf, he], axis=2)], axis=1)
        c = self._per_angle(self.local * self.local)
        ftf = np.einsum("nmr,nms->nrs", self.f, self.f, optimize=False)
        return IncrementsNormal(ww, cross, c, self.e * kt, v, ftf)


class IncrementsNormal:
    """J^T J of `Increments` (masked) = J0^T J0 + X S X^T: the leading block ww (N, p, p),
    the cross block (N, n, p) (W^T L E, transposed), the chain's c (N, n) and factors
    k (N, n), and the low-rank X (N, p + n, 2r) with S = [[0, I], [I, ftf]]."""

    def __init__(self, ww, cross, c, k, v, ftf) -> None:
        self.ww, self.cross, self.c, self.k, self.v, self.ftf = ww, cross, c, k, v, ftf

    def _sigma(self) -> np.ndarray:
        r = self.ftf.shape[1]
        sigma = np.zeros(self.ftf.shape[:1] + (2 * r, 2 * r))
        sigma[:, :r, r:] = sigma[:, r:, :r] = np.eye(r)
        sigma[:, r:, r:] = self.ftf
        return sigma

    def diagonal(self) -> np.ndarray:
        chain = self.k * self.k * np.flip(np.cumsum(np.flip(self.c, axis=1), axis=1), axis=1)
        low = np.einsum("nja,nab,njb->nj", self.v, self._sigma(), self.v, optimize=False)
        return np.concatenate([np.einsum("npp->np", self.ww), chain], axis=1) + low

    def matvec(self, damp: np.ndarray, x: np.ndarray) -> np.ndarray:
        """(J^T J + diag(damp)) x for x (N, p + n)."""
        p = self.ww.shape[1]
        xw, xt = x[:, :p], x[:, p:]
        top = linalg.matvec(self.ww, xw) + np.einsum("njp,nj->np", self.cross, xt, optimize=False)
        chain = self.k * np.flip(np.cumsum(np.flip(self.c * np.cumsum(self.k * xt, axis=1), axis=1), axis=1),
                                 axis=1)
        bottom = np.einsum("njp,np->nj", self.cross, xw, optimize=False) + chain
        vx = np.einsum("nlb,nl->nb", self.v, x, optimize=False)
        low = np.einsum("nja,nab,nb->nj", self.v, self._sigma(), vx, optimize=False)
        return np.concatenate([top, bottom], axis=1) + low + damp * x

    def _solve_m0(self, damp: np.ndarray, y: np.ndarray) -> np.ndarray:
        """(J0^T J0 + diag(damp)) x = y (N, p + n, R): the chain eliminated, then the
        leading block's Schur complement (positive definite: J0^T J0 is a Gram matrix)."""
        p = self.ww.shape[1]
        yw, yt = y[:, :p], y[:, p:]
        both = chain_solve(self.c, self.k, damp[:, p:], np.concatenate([self.cross, yt], axis=2))
        yc, yy = both[..., :p], both[..., p:]  # chain^-1 cross, chain^-1 y_t
        if p == 0:
            return yy
        schur = self.ww + np.einsum("np,pq->npq", damp[:, :p], np.eye(p)) \
            - np.einsum("njp,njq->npq", self.cross, yc, optimize=False)
        xw = linalg.solve_spd(schur, yw - np.einsum("njp,njr->npr", self.cross, yy, optimize=False))
        xt = yy - np.einsum("njp,npr->njr", yc, xw, optimize=False)
        return np.concatenate([xw, xt], axis=1)

    def solve(self, damp: np.ndarray, y: np.ndarray) -> np.ndarray:
        """x with (J^T J + diag(damp)) x = y, y (N, p + n) or (N, p + n, R): the low-rank
        part by Sherman-Morrison-Woodbury over `_solve_m0`,
        x = x0 - M0^-1 X (S^-1 + X^T M0^-1 X)^-1 X^T x0, S^-1 = [[-ftf, I], [I, 0]]."""
        vector = y.ndim == 2
        y = y[..., None] if vector else y
        both = self._solve_m0(damp, np.concatenate([y, self.v], axis=2))
        x0, mu = both[..., :y.shape[2]], both[..., y.shape[2]:]
        r = self.v.shape[2] // 2
        cap = np.zeros(mu.shape[:1] + (2 * r, 2 * r))
        cap[:, :r, :r] = -self.ftf
        cap[:, :r, r:] = cap[:, r:, :r] = np.eye(r)
        cap = cap + np.einsum("nja,njb->nab", self.v, mu, optimize=False)
        t = linalg.solve(cap, np.einsum("nja,njr->nar", self.v, x0, optimize=False))
        x = x0 - np.einsum("nka,nar->nkr", mu, t, optimize=False)
        return x[..., 0] if vector else x
