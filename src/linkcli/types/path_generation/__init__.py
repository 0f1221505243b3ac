"""Path generation: a coupler point through target points.

Its vocabulary, read by the problem-file reader and `linkcli bench`; the modules
(`schema`, `solve`, `sections`, `plot`) are imported on demand through the registry.
"""

from linkcli.registry import ProblemType

TYPE = ProblemType(
    package="path_generation",
    methods=("auto", "multistart", "least-squares", "differential-evolution", "de-polish"),
    default_sections=("lengths", "grashof", "transmission", "motion", "positions", "error", "solver"),
    sections=("lengths", "grashof", "transmission", "motion", "kinematics", "positions", "error",
              "solver", "tolerance", "forces", "strength"),
    tolerance=True,
    bench_settings=(("auto", None), ("least-squares", 50_000), ("de-polish", 200_000),
                    ("differential-evolution", 20_000), ("differential-evolution", 200_000)),  # (method, budget) for `linkcli bench`; None: the default budget
)
