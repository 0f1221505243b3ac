"""quick-return: crank-rockers and slider-cranks designed by time ratio K and swing or stroke.

Its vocabulary, read by the problem-file reader and `linkcli bench`; the modules (`schema`,
`solve`, `sections`, `plot`) are imported on demand through the registry. The numerics:
family.py (families, best member, closest member to a window), geometry.py (the
closed-form construction), transmission.py (worst transmission angle), maximize.py (the
one-dimensional max-min search), simulate.py (K and swing/stroke recomputed from lengths).
"""

from linkcli.registry import ProblemType

TYPE = ProblemType(
    package="quick_return",
    methods=("auto", "closed-form"),
    default_sections=("lengths", "grashof", "transmission", "motion", "family", "solver"),
    sections=("lengths", "grashof", "transmission", "motion", "kinematics", "family", "solver"),
    tolerance=False,
    bench_settings=(),  # (method, budget) for `linkcli bench`; None: the default budget
)
