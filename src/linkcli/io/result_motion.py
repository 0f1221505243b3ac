"""The motion study of a result file: the input speed and steps its kinematics used.

`synth --format toml` of a linkage writes them into the result's `[motion]` table (beside
the motion ranges it reports), with the same names and units as a problem file's
`[motion]`, so that `analyze` of the result reproduces the report. A result written
without them (older files) keeps the defaults, 1 angle unit per second and 360 steps.
"""

from __future__ import annotations

from dataclasses import replace

from linkcli.types.linkage.schema import MAX_STEPS
from linkcli.io.meta import MAX_LENGTH

REPORTED = ("input_full_turn", "input_range", "output_full_turn", "output_range",
            "output_swing", "time_ratio")  # linkcli's own output in [motion]: not read back


def motion_study(root, problem):
    """`problem` with input_speed (rad/s) and steps from the result's [motion] table, or
    None when they are bad (errors recorded on the reader)."""
    mot = root.table("motion")
    if mot is None:
        return problem
    mot.allow(*REPORTED)
    speed = mot.number("input_speed", 1.0, lo=-MAX_LENGTH, hi=MAX_LENGTH,
                       what="a non-zero number (angle unit per second)")
    if speed == 0.0:
        mot.error("input_speed", "a non-zero number (angle unit per second)", 0.0)
        speed = None
    steps = mot.number("steps", 360, integer=True, lo=2, hi=MAX_STEPS)
    if speed is None or steps is None:
        return None
    return replace(problem, input_speed=problem.meta.units.to_rad(speed), steps=steps)
