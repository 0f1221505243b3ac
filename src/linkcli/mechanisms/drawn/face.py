"""The drawn linkage's synthesis face (mechanisms.synthesis): no design type yet."""

from __future__ import annotations

from linkcli.mechanisms.synthesis import Face


class DrawnFace(Face):
    mechanism = "drawn"
    strategies = {}


FACE = DrawnFace()
