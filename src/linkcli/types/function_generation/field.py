"""The batched stage of `auto`: many candidates, each on its own branch, as one batch of
least-squares problems in the local linear unit box (numpy; no BLAS, no scipy).

A row's residuals are its angle errors at the points and the penalties of its constraints,

    r = (psi_k - psi_target_k for k = 1..M,  sqrt(W) min(g_i, 0) for each inequality
         g_i >= 0 of Model.inequalities,  sqrt(W) * the law's undefined share),

a quadratic penalty of weight W (`weight`). The Jacobian is taken by forward differences
(one batch of N n shifted rows, stepping inwards at the upper bound); a penalty's slope is
that of its constraint where the constraint is violated and 0 where it holds (a difference
of min(g, 0) across its kink gives half the slope, and the search would crawl along an
active constraint). Every row evaluated is counted and recorded by the Search.
linkcli.search.levenberg_marquardt.batch_lm solves the batch.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.types.function_generation.model import BRANCH_SIGN

STEP = 1e-7  # forward-difference step in the unit box


class Field:
    """The batch of `batch_lm` (linkcli.search.levenberg_marquardt.BoxedLeastSquares) for
    the rows of a field: their branch signs (N,) and the penalty weight."""

    def __init__(self, search, signs: np.ndarray, weight: float) -> None:
        self.search = search
        self.model = search.model
        self.signs = np.asarray(signs, dtype=float)
        self.root = math.sqrt(weight)
        n = self.model.n_variables
        self.lo, self.hi = np.zeros(n), np.ones(n)
        self.budget = search.evaluations

    def _parts(self, z: np.ndarray, signs: np.ndarray):
        """(errors (N, M), constraint values g (N, C), law's undefined share (N, 1)) of rows
        z of the local unit box on their branches; counted and recorded."""
        v = self.model.linear_values(z)
        batch = self.search.run_signed(v, signs)
        return batch.err, self.model.inequalities(v, signs[:, None]), batch.violation[:, -1:]

    def residuals(self, z: np.ndarray, rows) -> np.ndarray:
        err, g, law = self._parts(z, self.signs[rows])
        return np.concatenate([err, self.root * np.minimum(g, 0.0), self.root * law], axis=1)

    def jacobian(self, z: np.ndarray, rows, r0: np.ndarray) -> np.ndarray:
        """(N, m, n) slopes of the residuals r0 (N, m) at rows z by forward differences."""
        count, n = z.shape
        h = np.where(z > 1.0 - STEP, -STEP, STEP)
        shifted = (z[:, None, :] + np.eye(n)[None, :, :] * h[:, None, :]).reshape(count * n, n)
        err, g, _ = self._parts(shifted, np.repeat(self.signs[rows], n))
        m_err = err.shape[1]
        err = err.reshape(count, n, -1)
        g = g.reshape(count, n, -1)
        penalty = r0[:, m_err:m_err + g.shape[2]]
        violated = penalty < 0.0  # the slope of g where it is violated, else 0
        slope_err = (err - r0[:, None, :m_err]) / h[:, :, None]
        slope_pen = np.where(violated[:, None, :], (self.root * g - penalty[:, None, :]) / h[:, :, None], 0.0)
        slope_law = np.zeros((count, n, 1))
        return np.transpose(np.concatenate([slope_err, slope_pen, slope_law], axis=2), (0, 2, 1))


def signs_of(branches) -> np.ndarray:
    """Branch names -> their signs (-1 open, +1 crossed)."""
    return np.array([BRANCH_SIGN[b] for b in branches], dtype=float)
