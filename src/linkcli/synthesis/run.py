"""The shared search's entry (a home's synthesis face names `solve`): a problem with a topology
goes to the sweep over its catalogued drawings (synthesis.sweep), any other to the design of
its home's population (synthesis.design).
"""

from __future__ import annotations

from linkcli.solution import Solution


def solve(problem) -> Solution:
    """The design of a problem whose home offers a population (mechanisms.synthesis); with
    a topology, the sweep over its catalogued drawings (synthesis.sweep)."""
    from linkcli.mechanisms import synthesis
    if getattr(problem, "topology", None):
        from linkcli.synthesis.sweep import sweep
        return sweep(problem)
    from linkcli.synthesis.design import design
    return design(problem, synthesis.face(problem.mechanism).population(problem))
