"""Linkage: analysis of a given four-bar driven at a constant input speed (nothing to solve).

Its vocabulary, read by the problem-file reader and `linkcli bench`; the modules
(`schema`, `solve`, `sections`, `plot`) are imported on demand through the registry.
"""

from linkcli.registry import ProblemType

TYPE = ProblemType(
    package="linkage",
    methods=("auto",),
    default_sections=("lengths", "grashof", "transmission", "motion", "kinematics"),
    sections=("lengths", "grashof", "transmission", "motion", "kinematics", "tolerance", "forces", "strength"),
    tolerance=True,
    bench_settings=(),  # (method, budget) for `linkcli bench`; None: the default budget
)
