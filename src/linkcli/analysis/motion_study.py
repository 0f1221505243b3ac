"""The motion study's drive speed and step count, shared by the report's sections, the
dynamics' balance, the Pareto objectives and the animation. Pure Python."""

from __future__ import annotations


def motion_study(problem, u) -> tuple[float, int]:
    """(input speed in rad/s, steps) of the motion study: the problem's [motion], else 1 angle
    unit per second and 360 steps (types without [motion])."""
    return getattr(problem, "input_speed", None) or u.to_rad(1.0), getattr(problem, "steps", 360)
