"""Solvers, one module per problem type, each exposing `solve(problem) -> Solution`.

`solve` picks the module by the problem's type and imports it only then, so a
closed-form problem never imports scipy. Only modules under here import scipy.
"""

from __future__ import annotations

import importlib

SOLVERS = {
    "precision-position": "precision_position",
    "function-generation": "function_generation",
    "path-generation": "path_generation",
    "flipper-cylinder": "flipper_cylinder",
    "linkage": "linkage",
}


def solve(problem):
    """Solve one validated problem; non-convergence is a status of the Solution."""
    module = importlib.import_module(f"linkcli.solvers.{SOLVERS[problem.meta.type]}")
    return module.solve(problem)
