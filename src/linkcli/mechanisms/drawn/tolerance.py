"""A drawn linkage's made parts for the tolerance Monte Carlo (analysis.tolerance drives it).

Lengths. Each link (and the ground) is made from its joints' distances: its first two pinned
joints P1, P2 at |P1 P2| + dl along their drawn direction, and every further joint Pk at
|P1 Pk| + dl and |P2 Pk| + dl on the side it is drawn on (a triangle per joint: 2k - 3
independent distances for k joints, every distance of a binary or ternary link). The
[tolerance] `lengths` of a link applies to each of its distances; the columns are named
"link P1-P2" as in the report's linkage section.

Joint clearance (the effective-link model of Lee & Gilmore 1991 and Ting, Zhu & Watkins
2000, as the four-bar's): at every pin, each link but the one the pin belongs to (the pin
convention of drawn.loads; at a slider joint the link carrying the block) bears on it with
an offset anywhere in a disc of the radial clearance, drawn per target. A slider's play
(`clearance_slider`) shifts its guide along its normal by up to the play, per target.

Error of one sample: the largest distance, over the targets and the traced points
([motion] points, else every joint that moves), between the made linkage's point and the
nominal one, each made part assembled on the drawn branches at the targets (36 values of
the leading drive over the study's range: every 10 deg of a full turn, else the centres of 36
cells); it fails when a length comes out <= 0 or it cannot assemble at a target. A design
(path, motion or function generation, synthesis.schema) is measured where it
was designed: at its targets' drive values, on its target joint (path), its followed link's
frame origin (motion) or that link's angle (function: errors in radians), each against
the target, as a four-bar design is.
Sensitivity: per distance, the largest |d(point)/d(length)| over targets and points, by a
central difference on the nominal linkage.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from linkcli.mechanisms.drawn.loads import SLIDER, pin_bodies
from linkcli.mechanisms.drawn.solver import Kinematics
from linkcli.mechanisms.drawn.structure import GROUND

GRID = 36
NO_ALLOWED_ERROR = ("no allowed_error given: a sample fails only when it cannot be made (a length <= 0) "
                    "or assembled at a target")


def rigid_points(drawing, structure, body) -> list[str]:
    """The joints fixed on a body (not a driven slider running on its guide)."""
    return [j for j in structure.points[body]
            if drawing.joint(j).slider is None or (drawing.joint(j).guide or GROUND) != body]


def triangulation(drawing, structure) -> list[tuple[str, str, str, str | None]]:
    """(column name, body, joint, None | "first" | "second") of every toleranced distance:
    per body, its first two pinned joints and each further joint to both of them."""
    out = []
    bodies = [(GROUND, "ground")] + [(k.name, k.name) for k in drawing.links]
    for body, label in bodies:
        joints = rigid_points(drawing, structure, body)
        if len(joints) < 2:
            continue
        p1, p2 = joints[0], joints[1]
        out.append((f"{label} {p1}-{p2}", body, p2, None))
        for pk in joints[2:]:
            out.append((f"{label} {p1}-{pk}", body, pk, "first"))
            out.append((f"{label} {p2}-{pk}", body, pk, "second"))
    return out


class Model:
    """The drawn linkage's made parts (analysis.tolerance.Model)."""

    kind = "length"
    per_row = False  # the report gives the largest error over the steps only
    no_assembly = "the drawing does not close"
    no_allowed_error = NO_ALLOWED_ERROR

    def __init__(self, home, problem, solution=None):
        d = home.linkage
        sv = home.solved
        self.home, self.drawing, self.structure = home, d, sv.structure
        self.kin = sv.kin
        self.tri = triangulation(d, sv.structure)
        self.columns = tuple(name for name, _, _, _ in self.tri)
        self.inverse = self.columns
        self.link_of = {name: ("ground" if body == GROUND else body) for name, body, _, _ in self.tri}
        at = {j.name: np.array(j.at, dtype=float) for j in d.joints}
        self.lengths = {}
        for name, body, joint, which in self.tri:
            first, second = self._anchors(body)
            base = first if which in (None, "first") else second
            self.lengths[name] = float(np.linalg.norm(at[joint] - base))
        self.nominal = dict(self.lengths)  # column -> its drawn size (an ISO 2768 class's deviation: made_parts)
        self.keys = dict(self.link_of)  # column -> its [tolerance] lengths key: the link (made_parts.column_key)
        bodies = pin_bodies(d)
        self.bearings = []  # (body, joint) whose point carries a clearance offset
        for joint, bs in bodies.items():
            links = [b for b in bs[1:] if b not in (GROUND, SLIDER)]
            if not links and SLIDER in bs and bs[0] not in (GROUND, SLIDER):
                links = [bs[0]]
            self.bearings += [(b, joint) for b in links]
        self.pins = len(self.bearings)
        # fits (clearance = "fits"): each bearing's clearance from its joint's fit, drawn per
        # bearing (every link pinned there has its own bore on the pin); a slider's play from
        # its joint's fit (the block's width in its guide)
        self.pin_names = tuple(joint for _, joint in self.bearings)
        self.sliders = [j.name for j in d.joints if j.slider is not None]
        self.play_names = tuple(self.sliders)
        self.plays = len(self.sliders)
        self.traced = d.points or tuple(j.name for j in d.joints if not j.ground)
        self.measure = f"largest distance of {', '.join(self.traced)} from the nominal places"
        self.link = None  # a function design: the angle of this link is measured (kind "angle")
        kind = getattr(problem, "kind", None)
        if kind is not None and solution is not None:
            q = np.asarray(_design_inputs(solution, problem.meta.units), dtype=float)
            self.q, self.inputs = q, sv.start + q
            if kind == "function":
                self.kind, self.link = "angle", problem.link
                self.measure = f"deviation of link {problem.link}'s angle from the targets"
            else:
                self.traced = (problem.joint,) if kind == "path" else (d.link(problem.link).joints[0],)
                self.measure = f"distance of {self.traced[0]} from the targets"
        else:
            study = home.study()
            x, _ = study.rows(GRID)
            self.q = sv.q_of(x, study.full_turn)
            self.inputs = np.asarray(x, dtype=float)
        nominal = self.kin.run(self.q, rates=False)
        self.places = np.stack([nominal.pos[p] for p in self.traced], axis=1)  # (M, P, 2)
        self.angles = nominal.theta[self.link] if self.link is not None else None
        if kind is not None and solution is not None:  # a design misses its targets, not its nominal
            self.places, self.angles = _design_targets(solution, problem, sv, self.places, self.angles)
        from linkcli.mechanisms.drawn.schema import known_lengths
        from linkcli.mechanisms.drawn.sections import size
        self.scale = size(d)
        self.cap = min(self.lengths.values(), default=self.scale)
        self.known = known_lengths(d)

    def _anchors(self, body):
        joints = rigid_points(self.drawing, self.structure, body)
        return (np.array(self.drawing.joint(joints[0]).at), np.array(self.drawing.joint(joints[1]).at))

    # ------------------------------------------------------------ the protocol
    def column_scale(self, lengths: dict) -> np.ndarray:
        """A distance's tolerance: its own entry, else its link's."""
        return np.array([float(lengths.get(k, lengths.get(self.link_of[k], 0.0))) for k in self.columns])

    def given(self, tol) -> dict:
        return {"clearance_slider": float(tol.clearance_slider)} if self.sliders else {}

    def play_size(self, tol) -> float:
        return float(tol.clearance_slider) if self.sliders else 0.0

    def errors(self, dl, pins, plays):
        dist = self.deviations(dl, (pins, plays))
        ok = np.all(np.isfinite(dist), axis=1)
        err = np.where(ok, np.max(np.where(np.isfinite(dist), dist, 0.0), axis=1), np.inf)
        return err, ok

    def deviations(self, dl, terms):
        """(n, M) each made linkage's deviation at each target (the largest over the traced
        points, or the measured link's angle deviation), inf where it fails there."""
        pins, plays = terms
        places, ok, angles = self.made_places(dl, pins, plays, angles=True)
        if self.link is not None:
            dist = np.abs(np.angle(np.exp(1j * (angles - self.angles[None]))))
        else:
            dist = np.linalg.norm(places - self.places[None], axis=-1).max(axis=-1)  # (n, M)
        return np.where(ok & np.isfinite(dist), dist, np.inf)

    def sensitivity(self) -> dict:
        h = 1e-6 * self.scale
        c = len(self.columns)
        dl = np.concatenate([np.eye(c) * h, -np.eye(c) * h])
        places, ok, angles = self.made_places(dl, None, None, angles=True)
        if self.link is not None:
            slope = np.abs(np.angle(np.exp(1j * (angles[:c] - angles[c:])))).max(axis=1) / (2 * h)
        else:
            slope = np.linalg.norm(places[:c] - places[c:], axis=-1).max(axis=(1, 2)) / (2 * h)
        good = ok[:c].all(axis=1) & ok[c:].all(axis=1)
        return {name: (float(s) if g and math.isfinite(s) else None)
                for name, s, g in zip(self.columns, slope, good)}

    # ------------------------------------------------------------ made parts
    def made_places(self, dl, pins, plays, angles: bool = False):
        """(places (n, M, P, 2), ok (n, M)) of n made linkages at the M targets (and, with
        `angles`, the measured link's angle (n, M), or None)."""
        dl = np.asarray(dl, dtype=float)
        n, m = dl.shape[0], len(self.q)
        rows = n * m
        geo = self.kin.geometry
        local = dict(geo.local)
        made = np.ones(n, dtype=bool)
        lengths = {name: self.lengths[name] + dl[:, k] for k, name in enumerate(self.columns)}
        for name in lengths:
            made &= lengths[name] > 0
        for body in [GROUND] + [k.name for k in self.drawing.links]:
            rebuilt = self._rebuild(body, lengths, n)
            for joint, xy in rebuilt.items():
                local[(body, joint)] = np.repeat(xy, m, axis=0)
        if pins is not None:
            for k, (body, joint) in enumerate(self.bearings):
                base = np.broadcast_to(local[(body, joint)], (rows, 2))
                local[(body, joint)] = base + pins[:, :, k].reshape(rows, 2)
        guides = dict(geo.guides)
        if plays is not None:
            for k, joint in enumerate(self.sliders):
                body, g, beta = guides[joint]
                normal = np.array([-math.sin(beta), math.cos(beta)])
                guides[joint] = (body, g + plays[:, :, k].reshape(rows, 1) * normal, beta)
        made_geo = replace(geo, local=local, guides=guides)
        kin = Kinematics(self.drawing, self.structure, made_geo, tracks=self.kin.tracks)
        with np.errstate(all="ignore"):
            st = kin.run(np.tile(self.q, n), rates=False)
        places = np.stack([st.pos[p] for p in self.traced], axis=1).reshape(n, m, len(self.traced), 2)
        ok = st.valid.reshape(n, m) & made[:, None]
        if angles:
            return places, ok, (st.theta[self.link].reshape(n, m) if self.link is not None else None)
        return places, ok

    def _rebuild(self, body, lengths, n) -> dict:
        """A made body's points in its frame (n rows): P1 as drawn, P2 along the drawn
        direction at the made distance, Pk from its made distances to P1 and P2 on the drawn
        side (module docstring)."""
        entries = [(name, joint, which) for name, b, joint, which in self.tri if b == body]
        if not entries:
            return {}
        geo = self.kin.geometry
        joints = rigid_points(self.drawing, self.structure, body)
        p1, p2 = joints[0], joints[1]
        l1 = np.asarray(geo.local[(body, p1)], dtype=float)
        l2 = np.asarray(geo.local[(body, p2)], dtype=float)
        axis = (l2 - l1) / np.linalg.norm(l2 - l1)
        normal = np.array([-axis[1], axis[0]])
        out = {}
        d12 = lengths[f"{entries[0][0]}"]
        out[p2] = l1 + d12[:, None] * axis
        label = "ground" if body == GROUND else body
        for pk in joints[2:]:
            lk = np.asarray(geo.local[(body, pk)], dtype=float)
            side = 1.0 if np.dot(lk - l1, normal) >= 0 else -1.0
            r1, r2 = lengths[f"{label} {p1}-{pk}"], lengths[f"{label} {p2}-{pk}"]
            a = (r1 * r1 - r2 * r2 + d12 * d12) / (2.0 * d12)
            with np.errstate(invalid="ignore"):
                h = np.sqrt(r1 * r1 - a * a)  # NaN: a triangle the made lengths cannot close
            out[pk] = l1 + a[:, None] * axis + (side * h)[:, None] * normal
        return out


def model(home, problem, solution=None) -> Model:
    return Model(home, problem, solution)


def _design_targets(solution, problem, sv, places, angles):
    """What a design's made linkages must reproduce: the target points (path), the target
    poses' origins (motion), or the link's target angles (function, from its drawn angle), as
    a four-bar design's tolerance measures them (mechanisms.four_bar.tolerance.targets)."""
    pos = solution.positions
    if problem.kind == "path":
        return np.asarray(pos.target, dtype=float).reshape(-1, 1, 2), angles
    if problem.kind == "function":
        return places, sv.kin.geometry.angle0[problem.link] + np.asarray(pos.target, dtype=float)
    rows = solution.sections["positions"]
    return np.array([row["target"][:2] for row in rows], dtype=float).reshape(-1, 1, 2), angles


def _design_inputs(solution, units):
    """A design's targets' drive values (offsets from its drawing): its positions' inputs, or
    (motion generation, whose rows are its own section) the rows' inputs."""
    if solution.positions is not None:
        return solution.positions.input
    return [units.to_rad(row["input"]) for row in solution.sections["positions"]]

