"""The shared synthesis search: path, motion and function generation over any mechanism home
that offers a `Population` (mechanisms.synthesis) -- today the drawn linkage's.

    model.py     the problem over a population: variables (the home's, then the timing),
                 target residuals, constraint residuals (each the worst over the drive's
                 travel, refined to round-off), Jacobians
    starts.py    starting designs: the home's draws completed by timing hypotheses
    search.py    rounds of batched Levenberg-Marquardt from distinct starts, polish, the
                 Newton-KKT settle and the found-twice confirmation; the statuses
    solution.py  the Solution: the designed linkage, positions, timing, violations named
"""
