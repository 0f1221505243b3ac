"""Function generation: free lengths such that the output angle follows a law.

Its vocabulary, read by the problem-file reader and `linkcli bench`; the modules
(`schema`, `solve`, `sections`, `plot`) are imported on demand through the registry.
"""

from linkcli.registry import ProblemType

TYPE = ProblemType(
    package="function_generation",
    methods=("auto", "slsqp", "differential-evolution", "dual-annealing"),
    default_sections=("lengths", "grashof", "transmission", "motion", "positions", "error", "solver"),
    sections=("lengths", "grashof", "transmission", "motion", "kinematics", "positions", "error",
              "solver", "tolerance", "forces", "strength"),
    tolerance=True,
    bench_settings=(("auto", None), ("auto", 1000), ("slsqp", None), ("differential-evolution", None),
                    ("dual-annealing", 5000)),  # (method, budget) for `linkcli bench`; None: the default budget (4000 per variable)
)
