"""Flipper cylinder: a hydraulic cylinder turning a loaded platform about its hinge.

Its vocabulary, read by the problem-file reader and `linkcli bench`; the modules
(`schema`, `solve`, `sections`, `plot`) are imported on demand through the registry.
"""

from linkcli.registry import ProblemType

TYPE = ProblemType(
    package="flipper_cylinder",
    methods=("auto", "differential-evolution", "slsqp"),
    default_sections=("cylinder", "solver"),
    sections=("cylinder", "solver"),
    tolerance=False,
    bench_settings=(("auto", None), ("auto", 500), ("differential-evolution", None),
                    ("differential-evolution", 500), ("slsqp", None)),  # (method, budget) for `linkcli bench`; None: the default budget
)
