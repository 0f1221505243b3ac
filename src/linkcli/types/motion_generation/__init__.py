"""Motion generation (rigid-body guidance): a four-bar whose coupler carries a body
through given poses (x, y, angle).

Its vocabulary, read by the problem-file reader and `linkcli bench`; the modules
(`schema`, `solve`, `sections`, `plot`) are imported on demand through the registry. The
numerics: `poses` (poses and poles), `dyads` (2- and 3-pose dyads), `burmester` (the
centre-point curve of 4 poses, the Burmester dyads of 5), `assemble` (a four-bar from two
dyads, its defects), `least_squares` (more than five poses). Internally a pose is
(x, y, angle) with the angle in radians; a dyad is (G, M): ground pivot G in the global
frame, moving pivot M in the body frame.
"""

from linkcli.registry import ProblemType

TYPE = ProblemType(
    package="motion_generation",
    methods=("auto",),
    default_sections=("lengths", "grashof", "transmission", "motion", "positions", "error", "solver"),
    sections=("lengths", "grashof", "transmission", "motion", "kinematics", "positions", "error",
              "solver"),
    tolerance=False,
    bench_settings=(("auto", None),),  # (method, budget) for `linkcli bench`; None: the default budget
)
