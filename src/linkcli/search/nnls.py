"""Non-negative least squares, min |E y - f| subject to y >= 0, in numpy (no scipy).

Lawson & Hanson, "Solving Least Squares Problems" (1974), ch. 23, algorithm NNLS: an
active-set method. The passive set P (the y_j free to be positive) grows by the index
whose dual w_j = (E^T (f - E y))_j is largest and positive; the least-squares solution z
on P replaces y when every z_j > 0, else y moves towards z until a component reaches 0
and that index leaves P. At the end y >= 0, w <= 0 off P and w = 0 on P (the KKT
conditions). Each least-squares solve on P is numpy's `lstsq` (LAPACK): the callers use
NNLS inside steps whose end a BLAS-free Newton settle makes the same on every machine.
"""

from __future__ import annotations

import numpy as np


def nnls(e: np.ndarray, f: np.ndarray, maxiter: int | None = None) -> tuple[np.ndarray, float]:
    """(y, |E y - f|) of min |E y - f| over y >= 0 (Lawson & Hanson's NNLS). RuntimeError
    after `maxiter` inner iterations (default 3 n), as scipy.optimize.nnls raises."""
    e = np.asarray(e, dtype=float)
    f = np.asarray(f, dtype=float)
    m, n = e.shape
    maxiter = 3 * n if maxiter is None else int(maxiter)
    y = np.zeros(n)
    passive = np.zeros(n, dtype=bool)
    scale = float(np.max(np.sum(np.abs(e), axis=0), initial=0.0))
    tol = 10.0 * np.finfo(float).eps * scale * max(m, n)
    w = e.T @ f
    iterations = 0
    while not passive.all():
        candidates = np.where(passive, -np.inf, w)
        j = int(np.argmax(candidates))
        if candidates[j] <= tol:
            break
        passive[j] = True
        while True:
            iterations += 1
            if iterations > maxiter:
                raise RuntimeError("nnls: too many iterations")
            z = np.zeros(n)
            z[passive] = np.linalg.lstsq(e[:, passive], f, rcond=None)[0]
            if np.all(z[passive] > tol):
                y = z
                break
            blocking = passive & (z <= tol)
            alpha = float(np.min(y[blocking] / (y[blocking] - z[blocking])))
            y = y + alpha * (z - y)
            passive &= y > tol
            y[~passive] = 0.0
            if not passive.any():
                break
        w = e.T @ (f - e @ y)
    return y, float(np.linalg.norm(e @ y - f))
