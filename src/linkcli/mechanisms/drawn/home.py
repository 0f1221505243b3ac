"""A drawn linkage behind the mechanism protocol (mechanisms.protocol): its structure and
plan (structure), the plan run over rows (solver, groups), the drive's reach and the
extremes (motion), the report sections (sections), loads, made parts and drawing.

The leading drive (the first of [drive]) sets the rows: a turning drive's value is the
angle of the line from its ground pivot to the link's first other joint (global frame);
a sliding drive's, the slider's place along its guide, (J - O) . u with O the guide body's
frame origin (the global origin for a ground guide) and u the guide's direction. The other
drives move in proportion to their speeds (offsets from the drawing in the ratio of the
speeds). The solved drawing is cached per drawing (drawn.solved).
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.angles import wrap
from linkcli.mechanisms.drawn.solved import Solved, solved
from linkcli.mechanisms.protocol import LoadRows, Mechanism, Skeleton, Study

TWO_PI = 2.0 * math.pi


class DrawnStudy(Study):
    """The study of a drawn linkage: rows over the leading drive (full turn, its reach between
    dead points, or the [motion] span as far as it reaches)."""

    def __init__(self, full_turn, arc, detail, shortfall=None, span=None):
        super().__init__(full_turn, arc, detail, shortfall)
        object.__setattr__(self, "span", span)

    def rows(self, steps: int):
        """(x, shown): full turn k 2 pi / steps from 0; a rocking drive the centres of `steps`
        cells of its reach; a span `steps` values from its start to its end, ends included,
        as far as the drive reaches. Angles shown wrapped to (-180, 180] deg (a full turn:
        0 .. 360), lengths as they are."""
        sv = self.detail
        if self.span is not None:
            lo, hi = self.span
            x = lo + np.arange(steps) * ((hi - lo) / (steps - 1))
            a, b = self.arc
            x = x[(x >= a - 1e-12 * max(1.0, abs(a))) & (x <= b + 1e-12 * max(1.0, abs(b)))]
        elif self.full_turn:
            x = np.arange(steps) * (TWO_PI / steps)
            return x, x
        else:
            lo, hi = self.arc
            x = lo + (np.arange(steps) + 0.5) * ((hi - lo) / steps)
        return x, (wrap(x) if sv.turning else x)

    def printed(self, shown, units):
        shown = np.asarray(shown, dtype=float)
        return units.from_rad(shown) if self.detail.turning else shown

    def unit(self, units) -> str:
        return units.angle if self.detail.turning else units.length


class DrawnMechanism(Mechanism):
    name = "drawn"
    NO_ASSEMBLY = "the drawing does not close"
    DEAD_POINT = "a closure in line"
    TOGGLE = "the output stands still at an end of its travel"

    @property
    def solved(self) -> Solved:
        # kept on the home: the lru_cache key hashes the whole drawing, once per call (a
        # section asks a few hundred times: quadratic in the drawing's size)
        own = self.__dict__.get("_solved")
        if own is None:
            own = self.__dict__["_solved"] = solved(self.linkage)
        return own

    def size(self) -> float:
        from linkcli.mechanisms.drawn.sections import size
        return size(self.linkage)

    def lengths_section(self, units) -> dict:
        from linkcli.mechanisms.drawn.sections import linkage_section
        return linkage_section(self.linkage, units)

    def class_section(self, units) -> dict:
        from linkcli.mechanisms.drawn.sections import class_section
        return class_section(self.solved.structure)

    def study(self, near=None) -> Study:
        """Full turn, the reach between dead points, or the span (offsets from the drawing) as
        far as it reaches (a shortfall otherwise: exit 1 with the rows reached)."""
        sv = self.solved
        r = sv.reach
        span = self.linkage.span
        if span is None:
            if r.full_turn:
                return DrawnStudy(True, (0.0, TWO_PI), sv)
            return DrawnStudy(False, (sv.value(r.lo), sv.value(r.hi)), sv)
        lo, hi = span
        reach_lo, reach_hi = (-math.inf, math.inf) if r.full_turn else (r.lo, r.hi)
        shortfall = None
        if lo < reach_lo or hi > reach_hi:
            from linkcli.mechanisms.drawn.sections import shortfall_message
            shortfall = shortfall_message(self, lo, hi)
        a, b = max(lo, reach_lo), min(hi, reach_hi)
        if a > b:  # the span lies beyond a dead point: no row is reached; the range is that end
            a = b = reach_hi if lo > reach_hi else reach_lo
        return DrawnStudy(False, (sv.value(a), sv.value(b)), sv, shortfall,
                          span=(sv.value(lo), sv.value(hi)))

    def transmission_section(self, study, span, units, notes) -> dict:
        from linkcli.mechanisms.drawn.sections import transmission_section
        return transmission_section(self, study, units, notes)

    def motion_section(self, study, units) -> dict:
        from linkcli.mechanisms.drawn.sections import motion_section
        return motion_section(self, study, units)

    def kinematics_rows(self, study, speed, steps, units) -> list[dict]:
        from linkcli.mechanisms.drawn.sections import kinematics_rows
        return kinematics_rows(self, study, steps, units)

    def study_keys(self, speed, steps, units) -> dict:
        """The drives carry their speeds ([drive], echoed in `motion.drives`): steps only."""
        return {"steps": steps}

    def state(self, x, study: Study | None = None, rates: bool = True):
        """The solver's state at leading-drive values x (the study's rows)."""
        sv = self.solved
        full = sv.reach.full_turn if study is None else study.full_turn
        return sv.kin.run(sv.q_of(x, full), rates=rates)

    def load_rows(self, phi, speed, case, metres) -> LoadRows:
        """Pin forces by joint (drawn.loads: which link each acts on) at leading-drive values
        phi, the drives at their [drive] speeds."""
        from linkcli.mechanisms.drawn.loads import drawn_loads
        return drawn_loads(self, self.state(phi), case, metres)

    def member_forces(self, phi, speed, case, metres, rows):
        """Every link with its joints (a binary link a bar, more joints a plate, a binary link
        carrying a slider's guide no bar) and its loads; every pin joining two bodies or more
        (drawn.members: the shear of a pin of three or more bodies)."""
        from linkcli.mechanisms.drawn.members import drawn_members
        return drawn_members(self, self.state(phi), case, metres, rows)

    def study_speed(self, speed):
        """The leading drive's [drive] speed (rad/s): its kinematics and loads run at it."""
        return self.linkage.drives[0].speed

    def body_graph(self, case, metres):
        """Every link and slider block; pins and guides as drawn.loads names them; None unless
        one turning drive (mechanisms.drawn.dynamics)."""
        from linkcli.mechanisms.drawn.dynamics import body_graph
        return body_graph(self, case, metres)

    def coefficients(self, q, metres):
        from linkcli.mechanisms.drawn.dynamics import coefficients
        return coefficients(self, q, metres)

    def tolerance_model(self, problem, solution):
        from linkcli.mechanisms.drawn.tolerance import model
        return model(self, problem, solution)

    def input_origin(self) -> float:
        """A design's positions count the drive from the drawn position (synthesis.model):
        the leading drive's drawn value."""
        return float(self.solved.start)

    def skeleton(self, phi) -> Skeleton:
        """Every joint and link at leading-drive values phi; ground joints as pivots, slider
        joints as blocks on their guides (ground guides drawn), the asked points traced."""
        from linkcli.mechanisms.drawn.structure import GROUND
        from linkcli.mechanisms.protocol import Guide
        d = self.linkage
        st = self.state(np.atleast_1d(np.asarray(phi, dtype=float)), rates=False)
        joints = {j.name: np.where(st.valid[:, None], st.pos[j.name], np.nan) for j in d.joints}
        guides = tuple(Guide(tuple(j.at), j.slider, j.name) for j in d.joints
                       if j.slider is not None and self.solved.kin.geometry.guides[j.name][0] == GROUND)
        return Skeleton(joints=joints, links={k.name: k.joints for k in d.links},
                        ground=tuple(j.name for j in d.joints if j.ground), valid=st.valid,
                        guides=guides, sliders=tuple(j.name for j in d.joints if j.slider is not None),
                        traced=d.points)


HOME = DrawnMechanism
