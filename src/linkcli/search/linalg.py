"""Small dense linear algebra without BLAS or LAPACK: the same bits on every machine.

numpy's `@`, `np.dot` and `np.linalg` call OpenBLAS/LAPACK, whose kernels (chosen by CPU,
`OPENBLAS_CORETYPE`) sum in different orders and so round differently. A search whose
steps come from them follows the kernel: one machine's multistart lands on another exact
fit than another's. The systems of linkcli's searches are small (a few to a few dozen
unknowns) and many at once, so they are solved here with elementwise numpy, vectorized
over the stack, a loop over the columns only; sums of products are `np.einsum` with
`optimize=False` (numpy's own loops, never BLAS).

- `solve(a, b)`: Gaussian elimination with partial pivoting (Golub & Van Loan, Matrix
  Computations, 4th ed., alg. 3.4.1), for stacks of square systems.
- `solve_spd(a, b)`: the same without pivoting, for symmetric positive definite stacks
  (damped normal equations), where it is stable (Golub & Van Loan, section 4.2: the
  pivots are the D of a = L D L^T, all positive); about three times faster.
- `matvec`, `gram`, `dot`: products as explicit sums.
- `restricted(a, free)`: a system with some unknowns held (their rows and columns those
  of the identity), for active sets.

Rows whose pivot is 0 (singular to working precision) come back as NaN; callers test
for it (`np.isfinite`) instead of catching an exception.
"""

from __future__ import annotations

import numpy as np


def dot(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """sum_i x_i y_i over the last axis."""
    return np.einsum("...i,...i->...", x, y, optimize=False)


def matvec(a: np.ndarray, x: np.ndarray) -> np.ndarray:
    """(a x)_i = sum_j a_ij x_j, stacks over leading axes."""
    return np.einsum("...ij,...j->...i", a, x, optimize=False)


def gram(j: np.ndarray) -> np.ndarray:
    """j^T j: (..., m, n) -> (..., n, n)."""
    return np.einsum("...mi,...mj->...ij", j, j, optimize=False)


def restricted(a: np.ndarray, free: np.ndarray) -> np.ndarray:
    """a (N, n, n) with the rows and columns of the unknowns not `free` (N, n) replaced by
    those of the identity: solved with their value as right-hand side, they are held at
    it and the others solve the system restricted to the free ones."""
    held = ~free
    return (np.where(free[:, :, None] & free[:, None, :], a, 0.0)
            + np.where(held[:, :, None] & np.eye(a.shape[-1], dtype=bool), 1.0, 0.0))


def solve(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """x with a x = b for a (..., n, n) and b (..., n) (or (..., n, k)); a system whose
    elimination meets a zero pivot gets NaN.

    Forward elimination with partial pivoting (the largest remaining entry of the column
    swaps up, the first of equal ones), then back substitution."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    vector = b.ndim == a.ndim - 1
    if vector:
        b = b[..., None]
    n = a.shape[-1]
    stack = np.broadcast_shapes(a.shape[:-2], b.shape[:-2])
    a = np.broadcast_to(a, stack + (n, n)).reshape((-1, n, n)).copy()
    x = np.broadcast_to(b, stack + b.shape[-2:]).reshape((-1, n, b.shape[-1])).copy()
    _eliminate(a, x, pivoting=True)
    x = x.reshape(stack + x.shape[-2:])
    return x[..., 0] if vector else x


def solve_spd(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """x with a x = b for symmetric positive definite a (N, n, n) and b (N, n) (or
    (N, n, k): k right-hand sides); a system with a pivot that is not positive (not
    positive definite to working precision) gets NaN. Forward elimination without row
    swaps, then back substitution."""
    a = np.array(a, dtype=float)
    vector = np.ndim(b) == a.ndim - 1
    x = np.array(b, dtype=float)
    x = x[..., None] if vector else x
    _eliminate(a, x, pivoting=False)
    return x[..., 0] if vector else x


def _eliminate(a: np.ndarray, x: np.ndarray, pivoting: bool) -> None:
    """Solve the stack a (N, n, n) x = x (N, n, c) in place: forward elimination (with
    partial pivoting, or none: then a pivot must be positive), back substitution; rows
    whose elimination met a bad pivot become NaN. The forward sweep runs on [a | x] side
    by side (one update a column for both); a pivot stays on the diagonal once used, so
    the bad ones are read there at the end."""
    n = a.shape[-1]
    rows = np.arange(len(a))
    both = np.concatenate([a, x], axis=2)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for k in range(n):
            if pivoting:
                p = k + np.argmax(np.abs(both[:, k:, k]), axis=1)
                top, low = both[rows, k].copy(), both[rows, p].copy()
                both[rows, k], both[rows, p] = low, top
            factor = both[:, k + 1:, k] / both[:, k, k][:, None]
            both[:, k + 1:, k:] -= factor[:, :, None] * both[:, None, k, k:]
        a[...] = both[:, :, :n]
        x[...] = both[:, :, n:]
        pivots = np.diagonal(a, axis1=1, axis2=2)
        bad = ~np.all((np.abs(pivots) if pivoting else pivots) > 0.0, axis=1)
        for k in range(n - 1, -1, -1):
            s = np.einsum("rj,rjc->rc", a[:, k, k + 1:], x[:, k + 1:], optimize=False)
            x[:, k] = (x[:, k] - s) / a[:, k, k][:, None]
    x[bad] = np.nan
