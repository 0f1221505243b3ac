"""The planar five-bar with two drives: its home (kinematics, sections, made parts, drawing).

Light modules (no numpy): `model` (the dataclasses), `schema` (its [linkage] and [motion]
keys, and how the table report prints its class section and rows).
"""
