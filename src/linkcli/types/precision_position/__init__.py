"""Precision positions: Freudenstein function generation through paired positions.

Its vocabulary, read by the problem-file reader and `linkcli bench`; the modules
(`schema`, `solve`, `sections`, `plot`) are imported on demand through the registry.
"""

from linkcli.registry import ProblemType

TYPE = ProblemType(
    package="precision_position",
    methods=("auto", "freudenstein"),
    default_sections=("lengths", "grashof", "transmission", "motion", "positions", "error", "solver"),
    sections=("lengths", "grashof", "transmission", "motion", "kinematics", "positions", "error",
              "solver", "tolerance", "forces", "strength"),
    tolerance=True,
    bench_settings=(),  # (method, budget) for `linkcli bench`; None: the default budget
)
