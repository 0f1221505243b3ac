"""The objectives of a Pareto front, measured on one finished design (docs/pareto.md).

Every objective is computed from the design's Solution (its linkage, its targets, its working
span) through the mechanism protocol (`mechanisms.of(linkage)`), never asking which mechanism
it holds; the type's own least-squares residuals give `error` and `max-error` (its space,
linkcli.pareto.space). Values are in the report's units:

- `error`: the type's least-squares objective, sum of the squared residuals (rad^2 for angle
  errors, length^2 for points and poses: the report's `error.objective`);
- `max-error`: the largest error at a target (the angle unit, or the length unit: a target's
  residuals as one vector, so a pose's position and weighted angle errors together);
- `transmission`: the worst deviation of the transmission angle from 90 deg over the motion,
  max(90 - mu_min, mu_max - 90), from the home's transmission section (angle unit: its
  working range's extremes, or, where a home studies the motion itself -- the drawn home,
  over its linkage's span -- the section's own);
- `size`: the diagonal of the box swept by every joint and traced point (the coupler point)
  over the motion (length unit), from the home's skeleton at ROWS drive angles a turn, each
  joint's extreme coordinates refined on the skeleton (`Measure.peaks`);
- `link-ratio`: the longest link over the shortest (the home's links, schema.known_lengths);
- `torque`: the peak magnitude of the input torque over the motion's rows (N m), and
  `pin-force`: the peak pin force over every pin and row (N), from the home's load_rows under
  [loads]/[masses] at [motion] input_speed; a dead point in the motion makes them infinite;
- `failure-probability`: the tolerance section's failure probability, the share of the
  [tolerance] samples (seeded by [solver] seed, analysis.tolerance) whose largest error over
  the targets exceeds allowed_error.

The motion: the full turn of the input when the problem requires a class whose input turns
fully (the type's transmission window is then held over the full turn too), else the span of
the targets (the Solution's working span). Rows of a full turn are phi = 2 pi k / steps, the
kinematics and forces sections' rows; over a span, `steps` + 1 rows from its start to its end.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.mechanisms import of, schema_of

NAMES = ("error", "max-error", "transmission", "size", "link-ratio", "torque", "pin-force",
         "failure-probability")
ROWS = 720  # size: skeleton rows a full turn (an arc: its share of them, at least SPAN_ROWS)
SPAN_ROWS = 64
RIGHT = 0.5 * math.pi
TARGETED = ("error", "max-error")  # measured from the type's residuals (the timing moves them)
CACHED = 4096  # linkages whose protocol pieces are kept
PEAKS = 2  # the lifted size (boxes_many): peaks refined a joint's coordinate (its largest row and
# the next local maximum); the size's value and pieces refine the largest row alone
PEAK_WINDOW = 1e-3  # size: a local maximum within this share of the box's diagonal of a joint's largest
# row is refined too (the rows locate a peak within about 1e-5 of the diagonal: a rival peak further
# below cannot overtake the largest within a settle's steps)


def unit_of(name: str, units, error_kind: str) -> str:
    """The unit of an objective's values in the report."""
    if name == "error":
        return "rad^2" if error_kind == "angle" else f"{units.length}^2"
    if name == "max-error":
        return units.angle if error_kind == "angle" else units.length
    return {"transmission": units.angle, "size": units.length, "link-ratio": "1", "torque": "N m",
            "pin-force": "N", "failure-probability": "1"}[name]


class Measure:
    """The objectives of one problem, measured on designs of its space (`space.solution(x)`).

    `values(x)` are the report's numbers; `pieces(x)` the smooth functions whose largest is
    each value (a search holds an objective <= eps by holding every piece <= eps: a peak over
    rows moves from row to row, each row's value is smooth), with the failure probability
    replaced by its smoothed share on common draws (`Failure`) where the search needs slopes."""

    def __init__(self, problem, space, names: tuple[str, ...]) -> None:
        self.problem, self.space, self.names = problem, space, tuple(names)
        self.units = problem.meta.units
        from linkcli.analysis.motion_study import motion_study
        self.speed, self.steps = motion_study(problem, self.units)
        self.failure = None
        self.cache: dict = {}
        self.box_cache: dict = {}  # (linkage, peaks) -> its joints' peaks (boxes_many)

    def __getstate__(self):
        state = dict(self.__dict__)
        state["cache"] = {}  # a worker's own (the front's tasks pickle the measure each)
        state["box_cache"] = {}
        return state

    # ------------------------------------------------------------ the motion
    def motion(self, sol) -> tuple[float, float]:
        """(start, signed sweep) rad of the motion the objectives measure."""
        if self.space.full_turn or sol.working_span is None:
            return 0.0, 2.0 * math.pi
        return sol.working_span

    def rows(self, sol, count: int) -> np.ndarray:
        start, sweep = self.motion(sol)
        if abs(sweep) >= 2.0 * math.pi * (1 - 1e-12):
            return start + np.arange(count) * (2.0 * math.pi / count)
        return start + np.linspace(0.0, sweep, count + 1)

    # ------------------------------------------------------------ values
    def values(self, x) -> np.ndarray:
        """The objectives of design x, in the order asked (the report's numbers)."""
        sol = self.space.solution(x)
        return np.array([self.value(name, x, sol) for name in self.names], dtype=float)

    def snapped(self, values, sol) -> np.ndarray:
        """The values as the report prints them: round-off of an exact fit is 0 (the error
        section's noise floor: an objective below n (NOISE_FLOOR s)^2, a target's error below
        NOISE_FLOOR s, s = 1 rad for angles, the linkage's size for lengths)."""
        from linkcli.noise import NOISE_FLOOR, snap
        scale = 1.0 if self.space.error_kind == "angle" else of(sol.linkage).size()
        targets = int(np.max(self.space.groups)) + 1
        out = np.array(values, dtype=float)
        for k, name in enumerate(self.names):
            if name == "error":
                out[k] = snap(float(out[k]), targets * NOISE_FLOOR * scale * scale)
            elif name == "max-error":
                size = self.units.from_rad(scale) if self.space.error_kind == "angle" else scale
                out[k] = snap(float(out[k]), float(size))
        return out

    def value(self, name: str, x, sol) -> float:
        if name == "failure-probability":
            return failure_probability(self.problem, sol)
        p = self.piece(name, x, sol)
        return float(np.max(p)) if p.size and np.all(np.isfinite(p)) else math.inf

    def pieces_many(self, xs, wanted=None, sols=None) -> list[list[np.ndarray]]:
        """`pieces(x, wanted=wanted)` of every design of xs (N, n) (sols: their Solutions, if made
        already); the size of every design not kept measured at once (`size_pieces_many`: the
        same numbers), the rest design by design."""
        sols = [self.space.solution(x) for x in xs] if sols is None else sols
        known: list = [None] * len(sols)
        if "size" in self.names:
            k = self.names.index("size")
            todo = [i for i, sol in enumerate(sols) if self._kept(sol) is None]
            for i, p in zip(todo, self.size_pieces_many([sols[i] for i in todo])):
                known[i] = {k: p}
        return [self.pieces(x, sol, wanted, known[i]) for i, (x, sol) in enumerate(zip(xs, sols))]

    def _key(self, sol):
        key = (sol.linkage, None if self.space.full_turn else sol.working_span)
        try:
            hash(key)
        except TypeError:
            return None
        return key

    def _kept(self, sol):
        key = self._key(sol)
        return self.cache.get(key) if key is not None else None

    def pieces(self, x, sol=None, wanted=None, known=None) -> list[np.ndarray]:
        """Per objective, its pieces at design x (the failure probability: its smoothed share).
        What the protocol measures depends on the linkage and its motion alone: kept for
        CACHED linkages (a search's differences along a timing variable move neither).
        `wanted` (objective indices, or None: all): the targeted objectives and the failure
        probability outside it are not measured (None in their place). `known`: objective
        index -> its pieces, measured already (pieces_many)."""
        sol = self.space.solution(x) if sol is None else sol
        key = self._key(sol)
        own = self.cache.get(key) if key is not None else None
        out = []
        for k, name in enumerate(self.names):
            if name in TARGETED or name == "failure-probability":
                if wanted is not None and k not in wanted:
                    out.append(None)
                elif name in TARGETED:
                    out.append(self.piece(name, x, sol))
                else:
                    out.append(np.array([self.smoothed_failure(x)]))
            elif own is not None:
                out.append(own[k])
            elif known and k in known:
                out.append(known[k])
            else:
                out.append(self.piece(name, x, sol))
        if key is not None and own is None:
            if len(self.cache) >= CACHED:
                self.cache.clear()
            self.cache[key] = out
        return out

    def piece(self, name: str, x, sol) -> np.ndarray:
        if name == "error":
            r = self.space.residuals(np.asarray(x, float)[None, :])[0]
            return np.array([float(r @ r)])
        if name == "max-error":
            return self.target_errors(x)
        if name == "transmission":
            return self.transmission(sol)
        if name == "size":
            return self.size_pieces(sol)
        if name == "link-ratio":
            return link_ratios(sol.linkage)
        if name in ("torque", "pin-force"):
            return self.loads(sol, name)
        raise KeyError(name)

    def target_errors(self, x) -> np.ndarray:
        """Each target's error: the norm of its residuals (report units)."""
        r = self.space.residuals(np.asarray(x, float)[None, :])[0]
        groups = self.space.groups
        err = np.sqrt(np.bincount(groups, weights=r * r, minlength=int(groups.max()) + 1))
        return self.units.from_rad(err) if self.space.error_kind == "angle" else err

    def transmission(self, sol) -> np.ndarray:
        """(90 - mu_min, mu_max - 90) over the motion, the angle unit (inf: no assembly)."""
        mech = of(sol.linkage)
        start, sweep = self.motion(sol)
        study = mech.study(start)
        if study is None:  # one piece (a search that meets it mid-step: front.UNMEASURED)
            return np.array([math.inf])
        sec = mech.transmission_section(study, (start, sweep), self.units, [])
        lo, hi = sec.get("working_min"), sec.get("working_max")
        if "working_min" not in sec and "working_max" not in sec:  # a home whose study is the
            lo, hi = sec.get("min"), sec.get("max")  # motion itself (the drawn home: its span)
        if lo is None or hi is None:
            return np.array([math.inf])
        right = float(self.units.from_rad(RIGHT))
        return np.array([right - float(lo), float(hi) - right])

    def size(self, sol) -> float:
        """The diagonal of the box swept over the motion (module docstring)."""
        p = self.size_pieces(sol)
        return float(np.max(p)) if np.all(np.isfinite(p)) else math.inf

    def size_pieces(self, sol) -> np.ndarray:
        """sqrt((xmax_i - xmin_j)^2 + (ymax_k - ymin_l)^2) over every four joints i, j, k, l:
        the largest is the box's diagonal, and each is smooth in the design (a joint's
        extreme over the motion moves smoothly: its refined peak), where the diagonal
        itself bends when the joint that bounds the box changes."""
        return self.size_pieces_many([sol])[0]

    def size_rows(self, sol) -> tuple[int, bool]:
        """(skeleton rows, full turn) of the size's motion."""
        start, sweep = self.motion(sol)
        full = abs(sweep) >= 2.0 * math.pi * (1 - 1e-12)
        count = ROWS if full else max(SPAN_ROWS, int(math.ceil(ROWS * abs(sweep) / (2.0 * math.pi))))
        return count, full

    def size_pieces_many(self, sols) -> list[np.ndarray]:
        """`size_pieces` of many designs: those of one home and one row count measured at once
        (the home's `joint_paths`, vectorized over designs x drive angles: the same numbers
        as design by design)."""
        out = []
        for box in self.boxes_many(sols, peaks=1):
            if not np.all(np.isfinite(box)):
                out.append(np.full(box.shape[1] ** 4, math.inf))
                continue
            ext = np.max(np.array([1.0, -1.0, 1.0, -1.0])[:, None, None] * box, axis=2)  # (4, joints)
            width = np.maximum(ext[0][:, None] + ext[1][None, :], 0.0).reshape(-1)
            height = np.maximum(ext[2][:, None] + ext[3][None, :], 0.0).reshape(-1)
            out.append(np.sqrt(width[:, None] ** 2 + height[None, :] ** 2).reshape(-1))
        return out

    def boxes_many(self, sols, peaks: int = PEAKS) -> list[np.ndarray]:
        """Per design, its joints' peaks (4, joints, peaks): the largest x, the smallest x, the
        largest y and the smallest y of each joint over the motion (`peaks`: 1, the largest row
        refined; 2, and the next local maximum), inf where the linkage does not assemble; those
        of one home and one row count measured at once, each kept for CACHED linkages."""
        out: list = [None] * len(sols)
        groups: dict = {}
        for i, sol in enumerate(sols):
            key = self._key(sol)
            if key is not None and (key, peaks) in self.box_cache:
                out[i] = self.box_cache[key, peaks]
                continue
            groups.setdefault((type(of(sol.linkage)), *self.size_rows(sol)), []).append(i)
        for (home, count, full), members in groups.items():
            try:
                boxes = self._box_group(home, [sols[i] for i in members], count, full, peaks)
            except _MixedJoints:  # the designs' skeletons name different joints: one at a time
                boxes = [self._box_group(home, [sols[i]], count, full, peaks)[0] for i in members]
            for i, box in zip(members, boxes):
                out[i] = box
                key = self._key(sols[i])
                if key is not None:
                    if len(self.box_cache) >= CACHED:
                        self.box_cache.clear()
                    self.box_cache[key, peaks] = box
        return out

    def _box_group(self, home, sols, count: int, full: bool, peaks: int) -> list[np.ndarray]:
        phi = np.array([self.rows(sol, count) for sol in sols], dtype=float)  # (K, n)
        linkages = [sol.linkage for sol in sols]
        try:
            paths = home.joint_paths(linkages, phi)
        except ValueError as exc:
            raise _MixedJoints from exc
        pts = np.stack([np.asarray(p, dtype=float).reshape(len(sols), phi.shape[1], 2)
                        for p in paths.values()], axis=2)  # (K, n, joints, 2)
        joints = pts.shape[2]
        out = [np.full((4, joints, peaks), math.inf) for _ in sols]
        good = np.flatnonzero(np.all(np.isfinite(pts), axis=(1, 2, 3)))
        if good.size == 0:
            return out
        ext = self.peaks(home, [linkages[i] for i in good], phi[good], pts[good], full, peaks)
        box = np.stack([ext[0, 1.0], ext[0, -1.0], ext[1, 1.0], ext[1, -1.0]], axis=1)  # (K, 4, joints, peaks)
        for j, i in enumerate(good):
            out[i] = box[j]
        return out

    def peaks(self, home, linkages, phi, pts, full: bool, count: int = PEAKS) -> dict:
        """(coordinate, sign) -> (K, joints, count) each design's joints' peak coordinates over the
        motion (phi (K, n) its rows, pts (K, n, joints, 2) its skeleton there). A joint's peaks:
        its largest row and (count 2) the next largest local maximum of the rows within
        PEAK_WINDOW of it (the largest again where there is none), in the order of their rows, each refined by
        REFINE rounds of a parabola through the skeleton at its vertex and DELTAS either side
        (the home's joint_paths at any drive angle: a Newton step on the coordinate's slope, to
        round-off, so that each peak is smooth in the design, where their largest bends when
        two peaks of the motion trade places); an end of an open arc is exact; a design whose
        rows step backwards (or not at all) keeps its rows. The four (coordinate, sign) sets of
        every joint and peak of every design in one array: one joint_paths call a round."""
        designs, n, joints = pts.shape[0], pts.shape[1], pts.shape[2]
        step = (phi[:, 1] - phi[:, 0]) if n > 1 else np.zeros(designs)
        lo = np.minimum(phi[:, 0], phi[:, -1])[:, None, None, None, None]
        hi = np.maximum(phi[:, 0], phi[:, -1])[:, None, None, None, None]
        keys = [(k, sign) for k in (0, 1) for sign in (1.0, -1.0)]
        coord = np.array([k for k, _ in keys])
        signs = np.array([sign for _, sign in keys])
        vals = signs[:, None, None] * np.moveaxis(pts[..., coord], 3, 1)  # (K, 4, rows, joints)
        top = _peak_rows(vals, full, count)  # (K, 4, joints, count)
        kk = np.arange(designs)[:, None, None, None]
        sets = np.arange(len(keys))[None, :, None, None]
        own = np.arange(joints)[None, None, :, None]
        slot = np.arange(count)[None, None, None, :]
        sampled = vals[kk, sets, top, own]  # (K, 4, joints, PEAKS): each peak's row
        best = sampled.copy()
        centre = phi[kk, top]
        inner = np.ones_like(top, dtype=bool) if full else (top > 0) & (top < n - 1)
        inner = inner & (step > 0)[:, None, None, None]
        if n > 1 and np.any(step > 0):
            for divisor in (1.0, 16.0, 256.0):  # DELTAS: step, step / 16, step / 256
                delta = (step / divisor)[:, None, None, None]
                at = np.stack([centre - delta, centre, centre + delta], axis=-1)  # (K, 4, joints, PEAKS, 3)
                if not full:
                    at = np.clip(at, lo, hi)
                paths = home.joint_paths(linkages, at.reshape(designs, -1))
                pos = np.stack([np.asarray(p, dtype=float).reshape(designs, -1, 2) for p in paths.values()], axis=2)
                pos = pos.reshape(designs, len(keys), joints, count, 3, joints, 2)
                y = signs[:, None, None, None] * pos[kk, sets, own, slot, :, own, coord[None, :, None, None]]
                y0, y1, y2 = y[..., 0], y[..., 1], y[..., 2]
                curve = y0 - 2.0 * y1 + y2
                with np.errstate(all="ignore"):
                    shift = np.where(curve < 0, 0.5 * (y0 - y2) / curve, 0.0)
                shift = np.clip(np.where(np.isfinite(shift), shift, 0.0), -1.0, 1.0)
                new_centre = centre + shift * delta
                if not full:
                    new_centre = np.clip(new_centre, lo[..., 0], hi[..., 0])
                with np.errstate(all="ignore"):
                    vertex = y1 - 0.25 * (y0 - y2) * shift
                ok = inner & np.isfinite(vertex) & (vertex >= sampled)
                best = np.where(ok, vertex, sampled)
                centre = np.where(ok, new_centre, centre)
        return {key: key[1] * best[:, i] for i, key in enumerate(keys)}

    def loads(self, sol, name: str) -> np.ndarray:
        """|input torque| (N m) or every pin force's magnitude (N) at the motion's rows."""
        from linkcli.analysis.forces import metres_per_unit
        mech = of(sol.linkage)
        phi = self.rows(sol, self.steps)
        rows = mech.load_rows(phi, self.speed, self.problem.meta.loads, metres_per_unit(self.units))
        if np.any(rows.singular):
            return np.full(len(phi) * (1 if name == "torque" else len(rows.pin_names)), math.inf)
        if name == "torque":
            return np.abs(np.asarray(rows.input_torque, dtype=float))
        return np.concatenate([rows.magnitude(pin) for pin in rows.pin_names])

    # ------------------------------------------------------------ failure, smoothed
    def smoothed_failure(self, x) -> float:
        if self.failure is None:
            self.failure = Failure(self.problem, self.space)
        return self.failure.share(x)


def _peak_rows(vals, full: bool, count: int) -> np.ndarray:
    """(K, 4, joints, count) row indices of each joint's peaks (vals (K, 4, rows, joints): each
    joint's x, -x, y and -y, so that every extreme is a largest): its largest row and (count 2) the largest
    other local maximum (a row above the one before it and not below the one after it,
    cyclically over a full turn) within PEAK_WINDOW of the rows' box diagonal of it, or the largest
    row again, sorted by row (slots that keep their peak as the design moves, where an order by
    value would swap them as the two trade places)."""
    designs, sets, n, joints = vals.shape
    top = np.argmax(vals, axis=2)[:, :, None, :]  # (K, sets, 1, joints)
    if count == 1:
        return np.moveaxis(top, 2, 3)
    largest = np.take_along_axis(vals, top, axis=2)
    reach = np.max(largest, axis=(2, 3))  # (K, 4): the rows' box, x, -x, y, -y
    window = PEAK_WINDOW * np.hypot(reach[:, 0] + reach[:, 1], reach[:, 2] + reach[:, 3])
    ahead = np.empty(vals.shape, dtype=bool)  # row r below row r + 1 (the last: below the first, or never)
    np.less(vals[:, :, :-1], vals[:, :, 1:], out=ahead[:, :, :-1])
    if full:
        np.less(vals[:, :, -1], vals[:, :, 0], out=ahead[:, :, -1])
    else:
        ahead[:, :, -1] = False
    rising = np.roll(ahead, 1, axis=2)  # row r above row r - 1
    if not full:
        rising[:, :, 0] = True
    local = rising & ~ahead & (vals >= largest - window[:, None, None, None])
    np.put_along_axis(local, top, False, axis=2)  # the largest row is slot one already
    other = np.where(local, vals, -np.inf)
    second = np.argmax(other, axis=2)[:, :, None, :]
    found = np.take_along_axis(other, second, axis=2) > -np.inf
    rows = np.concatenate([top, np.where(found, second, top)], axis=2)  # (K, sets, 2, joints)
    return np.moveaxis(np.sort(rows, axis=2), 2, 3)


class _MixedJoints(Exception):
    """A group of designs whose skeletons name different joints (measured one at a time)."""


def link_ratios(linkage) -> np.ndarray:
    """Every link over every other (the largest: longest over shortest)."""
    lengths = np.array([abs(float(v)) for v in schema_of(linkage.mechanism).known_lengths(linkage).values()])
    if not np.all(lengths > 0):
        return np.full(len(lengths) * (len(lengths) - 1), math.inf)
    ratio = lengths[:, None] / lengths[None, :]
    return ratio[~np.eye(len(lengths), dtype=bool)]


def failure_probability(problem, sol) -> float:
    """The tolerance section's failure probability of the design (analysis.tolerance: the same
    samples, seed and count)."""
    from linkcli.analysis.made_parts import parts as made_parts
    from linkcli.analysis.tolerance import chunks, failures, plan_of, run
    tol = problem.meta.tolerance
    model = of(sol.linkage).tolerance_model(problem, sol)
    if len(model.inputs) == 0:
        return 1.0
    parts = made_parts(model, problem)
    plan = plan_of(model, parts, tol.samples, tol.distribution)
    with np.errstate(all="ignore"):
        err, ok = run(model, chunks(int(problem.meta.solver.seed), plan), parts)
    return failures(err, ok, tol.allowed_error) / tol.samples


class Failure:
    """The failure probability as a search sees it: the share of SEARCH_SAMPLES common draws
    (analysis.robust_design.Study: the same draws at every design) whose largest deviation over
    the targets exceeds allowed_error, each sample's indicator smoothed (logistic, bandwidth
    SMOOTH allowed_error) so that the share is smooth in the design."""

    def __init__(self, problem, space) -> None:
        from linkcli.analysis.robust_design import SEARCH_SAMPLES, Study
        tol = problem.meta.tolerance
        self.study = Study(problem, space, min(tol.samples, SEARCH_SAMPLES))

    def share(self, x) -> float:
        from linkcli.analysis.robust_design import SMOOTH
        with np.errstate(all="ignore"):
            dev = self.study.deviations(np.asarray(x, float))
            worst = np.max(dev, axis=1)
            allowed = self.study.allowed
            z = np.clip((worst - allowed) / (SMOOTH * allowed), -40.0, 40.0)
            return float(np.mean(np.where(np.isfinite(worst), 1.0 / (1.0 + np.exp(-z)), 1.0)))
