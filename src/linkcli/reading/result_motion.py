"""The motion study of a result file: the input speed and steps its kinematics used.

`synth --format toml` of a linkage writes them into the result's `[motion]` table (beside
the motion ranges it reports), with the same names and units as a problem file's
`[motion]`, so that `analyze` of the result reproduces the report. A result written
without them (older files) keeps the defaults, 1 angle unit per second and 360 steps.
"""

from __future__ import annotations

from dataclasses import replace

from linkcli.mechanisms import schema_of

REPORTED = ("input_full_turn", "input_range", "output_full_turn", "output_range",
            "output_swing", "time_ratio")  # linkcli's own output in [motion]: not read back


def motion_study(root, problem):
    """`problem` with input_speed (rad/s) and steps from the result's [motion] table (and,
    for a mechanism with its own [motion], its rows: its schema's `read_motion`), or
    None when they are bad (errors recorded on the reader)."""
    own = schema_of(problem.linkage.mechanism)
    mot = root.table("motion")
    if mot is not None:
        mot.allow(*REPORTED, *own.reported_motion)
    study = own.read_motion(root, problem.meta, problem.linkage)
    if study is None:
        return None
    linkage, speed, steps = study
    return replace(problem, linkage=linkage, input_speed=speed, steps=steps)
