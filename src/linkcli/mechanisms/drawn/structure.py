"""The structure of a drawn linkage: its bodies and constraints, its mobility, and the order
in which the drives determine it (Assur groups from the drives outwards). Pure Python:
`check` finds every structural error without numpy.

Bodies are the ground and the links. A slider block is eliminated: an undriven slider joint
J on the guide of body G is the constraint "the point J of the links pinned there lies on
G's guide line" (one equation: the block adds three unknowns and four equations); a driven
slider joint is a point of its guide body at the drive's offset (the drive fixes the block
to the guide). A joint J pins the bodies at J: the ground (a ground joint), the guide body
(a driven slider) and every link listing J except the guide link of an undriven slider.

Counting (Gruebler-Kutzbach with sliders): with n bodies (ground, links and blocks), R
revolute pairs (k - 1 at a joint joining k bodies) and P prismatic pairs,
mobility = 3 (n - 1) - 2 R - 2 P. The plan (Assur decomposition, as Pyslvs's triangle
stack or pylinkage's solve order, but over bodies): repeatedly the smallest set S of
undetermined bodies whose equations with the determined ones equal 3 |S| is determined
next -- one body (a driven crank `Turn`; a link on one known pin whose slider joint runs on a
known guide `OnGuide`, RRP; a guide body on one known pin whose guide passes a known slider
joint `GuideThrough`, RPR), two bodies pinned together and each to one known joint (`Dyad`,
RRR), or a larger group (`Group`, a class-III triad and the like: Newton). Each closed form
keeps the side its joint is drawn on (`side`). A set with more equations than 3 |S| is not
rigid (its lengths contradict each other except at the drawing); bodies no set determines
are a loop the drives leave free.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from linkcli.mechanisms.drawn.model import SLIDE, TURN, Drawn

GROUND = ""  # the ground's body name (no link may be named so: TOML keys are non-empty here)
MAX_GROUP = 6  # links in a group solved by Newton (a class-III triad has 4, a tetrad 6)
SEARCH_BUDGET = 20_000  # connected sets examined when looking for a group
DEAD_RTOL = 1e-9  # a closure drawn with |sin| below this is drawn at a dead point


@dataclass(frozen=True)
class Problem:
    """A structural error: the file's key path it belongs to, what was expected, what was found."""

    where: tuple[str, ...]
    expected: str
    found: str


@dataclass(frozen=True)
class Turn:
    """A driven link turning about its ground joint `pivot` (drive number `drive`)."""

    link: str
    pivot: str
    drive: int


@dataclass(frozen=True)
class Dyad:
    """RRR: `first` (pinned at the known joint `first_at`) and `second` (at `second_at`) pinned
    together at `joint`, on the side `side` of first_at -> second_at (+1 left, -1 right)."""

    joint: str
    first: str
    first_at: str
    second: str
    second_at: str
    side: int


@dataclass(frozen=True)
class OnGuide:
    """RRP: `link` pinned at the known joint `at`; its slider joint `joint` on the known guide of
    `guide`; `side` = sign of (joint - at) . u along the guide direction u, as drawn."""

    link: str
    at: str
    joint: str
    guide: str
    side: int


@dataclass(frozen=True)
class GuideThrough:
    """RPR: the guide body `link` pinned at the known joint `at`; its guide passes the known
    slider joint `joint`; `side` = sign of (joint - at) . u, as drawn."""

    link: str
    at: str
    joint: str
    side: int


@dataclass(frozen=True)
class Group:
    """Links determined together by Newton's method from the drawing (not a dyad)."""

    links: tuple[str, ...]


def placed_by(op) -> set[str]:
    """The bodies an op of the plan places: a dyad's two links, a turn's or a slider group's
    link, a Newton group's links."""
    if isinstance(op, Dyad):
        return {op.first, op.second}
    if isinstance(op, (Turn, OnGuide, GuideThrough)):
        return {op.link}
    return set(op.links)


@dataclass
class Structure:
    """A drawn linkage's bodies and plan. pins: joint -> bodies pinned there (ground first,
    then the links in file order); slides: undriven slider joint -> its guide body; points:
    body -> its rigid points (the joints it is pinned at); plan: the ops in solve order;
    closures: (joint, link, other) of every closure, where its transmission angle is measured
    (`other`: the second link, or the guide body of a slider)."""

    drawing: Drawn
    pins: dict[str, tuple[str, ...]]
    slides: dict[str, str]
    points: dict[str, tuple[str, ...]]
    mobility: int
    bodies: int
    revolute_pairs: int
    prismatic_pairs: int
    plan: list = field(default_factory=list)
    problems: list[Problem] = field(default_factory=list)

    @property
    def links(self) -> tuple[str, ...]:
        return tuple(k.name for k in self.drawing.links)

    def closures(self) -> list[Closure]:
        """Every closure of the plan, where a transmission angle is measured."""
        out = []
        for op in self.plan:
            if isinstance(op, Dyad):
                out.append(Closure(op.joint, (op.first, op.second), "pin", op.first_at, op.second_at))
            elif isinstance(op, OnGuide):
                out.append(Closure(op.joint, (op.link, op.guide), "guide", op.at))
            elif isinstance(op, GuideThrough):
                carrier = next(b for b in self.pins[op.joint] if b != op.link)
                out.append(Closure(op.joint, (carrier, op.link), "guide", op.at))
            elif isinstance(op, Group):
                members = set(op.links)
                for joint, bodies in self.pins.items():
                    inside = [b for b in bodies if b in members]
                    if len(inside) == 2 and len(bodies) == 2:
                        ends = [next(p for p in self.points[b] if p != joint) for b in inside]
                        out.append(Closure(joint, tuple(inside), "pin", ends[0], ends[1]))
        return out


@dataclass(frozen=True)
class Closure:
    """Where a transmission angle is measured: the free `joint` of a closure and the two
    bodies meeting there. kind "pin": the angle at `joint` between the lines to `first`
    and `second` (each link's other joint of the closure; in a group, its next listed
    joint); kind "guide": the arm `joint` - `first` against the slider's guide."""

    joint: str
    links: tuple[str, str]
    kind: str
    first: str
    second: str = ""


def describe_plan(structure: Structure) -> list[str]:
    """The plan in words, one entry per group: `crank turns about O2`, `RRR at B (coupler,
    rocker)` ..."""
    words = []
    for op in structure.plan:
        if isinstance(op, Turn):
            words.append(f"{op.link} turns about {op.pivot}")
        elif isinstance(op, Dyad):
            words.append(f"RRR at {op.joint} ({op.first}, {op.second})")
        elif isinstance(op, OnGuide):
            words.append(f"RRP at {op.joint} ({op.link} on the guide of {op.guide or 'the ground'})")
        elif isinstance(op, GuideThrough):
            words.append(f"RPR at {op.joint} ({op.link}'s guide)")
        else:
            words.append(f"group of {len(op.links)} ({', '.join(op.links)}): Newton")
    return words


# ---------------------------------------------------------------- topology

def analyse(drawing: Drawn) -> Structure:
    """The structure, the mobility and the plan; `problems` lists what makes the drawing
    unusable (empty when the plan determines every link)."""
    joints = {j.name: j for j in drawing.joints}
    guide_of = {j.name: (j.guide or GROUND) for j in drawing.joints if j.slider is not None}
    driven_slides = {d.name for d in drawing.drives if d.kind == SLIDE}
    pins: dict[str, list[str]] = {name: [] for name in joints}
    for name, joint in joints.items():
        if joint.ground:
            pins[name].append(GROUND)
        if name in driven_slides and guide_of[name] == GROUND:
            pins[name].append(GROUND)
    for link in drawing.links:
        for name in link.joints:
            if guide_of.get(name) == link.name and name not in driven_slides:
                continue  # the guide of an undriven slider: not pinned there
            if guide_of.get(name) == link.name:
                continue  # a driven slider on this link's guide: added below, after the carriers
            pins[name].append(link.name)
    for name in driven_slides:
        if guide_of[name] != GROUND:
            pins[name].append(guide_of[name])
    slides = {name: guide for name, guide in guide_of.items() if name not in driven_slides}
    points: dict[str, list[str]] = {GROUND: []}
    for link in drawing.links:
        points[link.name] = []
    for name, bodies in pins.items():
        for body in bodies:
            points[body].append(name)
    blocks = len(guide_of)
    revolute = sum(len(bodies) - 1 for bodies in pins.values() if bodies)
    revolute += sum(1 for name in guide_of)  # each block is pinned to its carriers: one more body at J
    # (a driven slider's guide body was counted among its pins: the block takes its place there)
    revolute -= sum(1 for name in driven_slides)
    n = 1 + len(drawing.links) + blocks
    mobility = 3 * (n - 1) - 2 * revolute - 2 * blocks
    structure = Structure(drawing, {k: tuple(v) for k, v in pins.items()}, slides,
                          {k: tuple(v) for k, v in points.items()}, mobility, n, revolute, blocks)
    if mobility != len(drawing.drives):
        structure.problems.append(_mobility_problem(structure))
        return structure
    _plan(structure)
    return structure


def _mobility_problem(s: Structure) -> Problem:
    drives = len(s.drawing.drives)
    plural = "" if drives == 1 else "s"
    counted = (f"mobility {s.mobility} (Gruebler-Kutzbach: 3 (n - 1) - 2 R - 2 P with n = {s.bodies} "
               f"bodies, R = {s.revolute_pairs} pin pairs, P = {s.prismatic_pairs} sliders)")
    if s.mobility > drives:
        # name the joints the drives leave free: plan as far as the drives reach
        probe = Structure(s.drawing, s.pins, s.slides, s.points, s.mobility, s.bodies,
                          s.revolute_pairs, s.prismatic_pairs)
        free = _plan(probe, quiet=True)
        where = f": joints {', '.join(free)} are not determined by the drive{plural}" if free else ""
        return Problem(("drive",), f"{_drives(s.mobility)}, one per degree of freedom ({counted})",
                       f"{drives} drive{plural}{where}")
    return Problem(("drive",), f"{_drives(s.mobility)}, one per degree of freedom ({counted})" if s.mobility > 0
                   else f"a linkage that can move ({counted}: a structure)",
                   f"{drives} drive{plural}")


# ---------------------------------------------------------------- the plan

class _Count:
    """Equations between a set of undetermined bodies and the determined ones."""

    def __init__(self, s: Structure, known: set[str], turning: dict[str, int]):
        self.s, self.known, self.turning = s, known, turning
        self.body_joints = {body: pts for body, pts in s.points.items()}
        self.slides_of: dict[str, list[str]] = {}
        for joint, guide in s.slides.items():
            for body in set(s.pins[joint]) | {guide}:
                self.slides_of.setdefault(body, []).append(joint)

    def equations(self, group: set[str]) -> int:
        count, seen = 0, set()
        for body in group:
            for joint in self.body_joints[body]:
                if joint in seen:
                    continue
                seen.add(joint)
                bodies = self.s.pins[joint]
                inside = sum(1 for b in bodies if b in group)
                fixed = any(b in self.known for b in bodies)
                count += 2 * inside if fixed else 2 * (inside - 1)
            if body in self.turning:
                count += 1
        for joint in {j for body in group for j in self.slides_of.get(body, ())}:
            guide, carriers = self.s.slides[joint], self.s.pins[joint]
            placed = group | self.known
            if guide in placed and any(b in placed for b in carriers):
                count += 1
        return count

    def neighbours(self, body: str) -> list[str]:
        out = []
        for joint in self.body_joints[body]:
            out.extend(self.s.pins[joint])
        for joint in self.slides_of.get(body, ()):
            out.extend(self.s.pins[joint])
            out.append(self.s.slides[joint])
        return [b for b in dict.fromkeys(out) if b != body and b != GROUND]


def _plan(s: Structure, quiet: bool = False) -> list[str]:
    """Fill s.plan (and s.problems unless `quiet`); return the joints left undetermined."""
    drawing = s.drawing
    turning = {d.name: k for k, d in enumerate(drawing.drives) if d.kind == TURN}
    known = {GROUND}
    count = _Count(s, known, turning)
    order = {name: k for k, name in enumerate(s.links)}
    unknown = [name for name in s.links]
    queue = list(unknown)
    queued = set(queue)

    def place(op, bodies) -> None:
        s.plan.append(op)
        for body in bodies:
            known.add(body)
            unknown.remove(body)
        for body in bodies:
            for other in count.neighbours(body):
                if other not in known and other not in queued:
                    queue.append(other)
                    queued.add(other)

    while unknown:
        while queue:
            body = queue.pop(0)
            queued.discard(body)
            if body in known:
                continue
            eq = count.equations({body})
            if eq > 3:
                if not quiet:
                    s.problems.append(_over(s, {body}, eq))
                return []
            if eq == 3:
                op = _single(s, body, known, turning)
                place(op, [body])
                continue
            for other in sorted(count.neighbours(body), key=lambda b: order[b]):
                if other in known:
                    continue
                eq2 = count.equations({body, other})
                if eq2 == 6:
                    pair = sorted((body, other), key=lambda b: order[b])
                    place(_pair(s, pair, known), pair)
                    break
                if eq2 > 6:
                    if not quiet:
                        s.problems.append(_over(s, {body, other}, eq2))
                    return []
        if not unknown:
            break
        group, over = _find_group(s, count, unknown, order)
        if over is not None:
            if not quiet:
                s.problems.append(_over(s, over, count.equations(over)))
            return []
        if group is None:
            free = [j for j in (k.name for k in drawing.joints)
                    if s.pins[j] and not any(b in known for b in s.pins[j])]
            if not quiet:
                s.problems.append(Problem(("links",), "a linkage the drives determine (every loop closed by "
                                          "the drives and the drawing)",
                                          f"joints {', '.join(free)} free to move with the drives held "
                                          f"(links {', '.join(unknown)})"))
            return free
        place(Group(tuple(sorted(group, key=lambda b: order[b]))), sorted(group, key=lambda b: order[b]))
    if not quiet:
        _check_sides(s)
    return []


def _find_group(s: Structure, count: _Count, unknown: list[str], order: dict):
    """(smallest connected set of 3..MAX_GROUP undetermined links whose equations equal
    3 |S|, None) -- or (None, a set with more equations than unknowns) -- or (None, None)."""
    budget = [SEARCH_BUDGET]
    pool = set(unknown)
    for size in range(3, min(MAX_GROUP, len(unknown)) + 1):
        for start in sorted(unknown, key=lambda b: order[b]):
            found = _extend(count, {start}, start, size, pool, order, budget)
            if found is not None:
                eq = count.equations(found)
                return (found, None) if eq == 3 * size else (None, found)
            if budget[0] <= 0:
                break
    rest = set(unknown)
    eq = count.equations(rest)
    if eq > 3 * len(rest):
        return None, rest
    if eq == 3 * len(rest) and len(rest) <= MAX_GROUP:
        return rest, None
    return None, None


def _extend(count, group, start, size, pool, order, budget):
    """A connected set of `size` containing `group` (members after `start` in file order) whose
    equations reach 3 |S| (exactly: a group; more: over-constrained); None."""
    if budget[0] <= 0:
        return None
    budget[0] -= 1
    if len(group) == size:
        return group if count.equations(group) >= 3 * size else None
    frontier = sorted({n for b in group for n in count.neighbours(b)
                       if n in pool and n not in group and order[n] > order[start]},
                      key=lambda b: order[b])
    for nxt in frontier:
        found = _extend(count, group | {nxt}, start, size, pool, order, budget)
        if found is not None:
            return found
    return None


def _over(s: Structure, group: set[str], eq: int) -> Problem:
    links = sorted(group, key=lambda b: s.links.index(b))
    joints = [j for j in (k.name for k in s.drawing.joints)
              if any(b in group for b in s.pins[j]) or (j in s.slides and s.slides[j] in group)]
    return Problem(("links", links[0]), "a drawing whose links can move (each closure fixed once)",
                   f"links {', '.join(links)} held by {eq} equations for {3 * len(group)} unknowns: "
                   f"the distances between joints {', '.join(joints)} contradict the other loops "
                   "away from the drawing (not rigid)")


def _single(s: Structure, body: str, known: set[str], turning: dict[str, int]):
    """The one-body op that determines `body` (three equations)."""
    fixed = [j for j in s.points[body] if any(b in known for b in s.pins[j])]
    if body in turning:
        return Turn(body, fixed[0], turning[body])
    if len(fixed) == 1:
        at = fixed[0]
        for joint, guide in s.slides.items():
            carriers = s.pins[joint]
            if body in carriers and guide in known:
                return OnGuide(body, at, joint, guide, _side_on_guide(s, at, joint))
            if guide == body and any(b in known for b in carriers):
                return GuideThrough(body, at, joint, _side_on_guide(s, at, joint))
    return Group((body,))


def _pair(s: Structure, pair: list[str], known: set[str]):
    """RRR when the two are pinned together and each at one known joint; else a group."""
    first, second = pair
    shared = [j for j in s.points[first] if second in s.pins[j] and not any(b in known for b in s.pins[j])]
    fixed1 = [j for j in s.points[first] if any(b in known for b in s.pins[j])]
    fixed2 = [j for j in s.points[second] if any(b in known for b in s.pins[j])]
    if len(shared) == 1 and len(fixed1) == 1 and len(fixed2) == 1:  # the six equations are these pins
        joint = shared[0]
        return Dyad(joint, first, fixed1[0], second, fixed2[0], _side(s, fixed1[0], fixed2[0], joint))
    return Group(tuple(pair))


def _at(s: Structure, joint: str) -> tuple[float, float]:
    return s.drawing.joint(joint).at


def _side(s: Structure, a: str, b: str, joint: str) -> int:
    (ax, ay), (bx, by), (jx, jy) = _at(s, a), _at(s, b), _at(s, joint)
    cross = (bx - ax) * (jy - ay) - (by - ay) * (jx - ax)
    return 1 if cross >= 0 else -1


def _side_on_guide(s: Structure, at: str, joint: str) -> int:
    (ax, ay), (jx, jy) = _at(s, at), _at(s, joint)
    angle = s.drawing.joint(joint).slider
    dot = (jx - ax) * math.cos(angle) + (jy - ay) * math.sin(angle)
    return 1 if dot >= 0 else -1


def _check_sides(s: Structure) -> None:
    """A closure drawn at its dead point (the two links in line; the rod normal to the guide; a
    group's equations singular: group_lock) has no side to keep: refused, naming the joint (the
    group's first link)."""
    for op in s.plan:
        if isinstance(op, Dyad):
            (ax, ay), (bx, by), (jx, jy) = _at(s, op.first_at), _at(s, op.second_at), _at(s, op.joint)
            u, v = (jx - ax, jy - ay), (jx - bx, jy - by)
            size = math.hypot(*u) * math.hypot(*v)
            if size == 0 or abs(u[0] * v[1] - u[1] * v[0]) <= DEAD_RTOL * size:
                s.problems.append(Problem(("joints", op.joint), f"joint {op.joint} drawn off the line of "
                                          f"{op.first_at} and {op.second_at} (the closure of {op.first} and "
                                          f"{op.second} keeps the side it is drawn on)",
                                          f"{op.joint} drawn in line with them (a dead point: no side)"))
        elif isinstance(op, Group):
            from linkcli.mechanisms.drawn.group_lock import lock_ratio
            ratio = lock_ratio(s, op.links)
            if ratio is not None and ratio <= DEAD_RTOL:
                s.problems.append(Problem(("links", op.links[0]), f"links {', '.join(op.links)} drawn off a dead "
                                          "point of theirs (the group keeps the branch it is drawn on)",
                                          f"them drawn locked (|det J| / prod |columns| below {DEAD_RTOL:g} at "
                                          "the drawing: a dead point, no branch)"))
        elif isinstance(op, (OnGuide, GuideThrough)):
            (ax, ay), (jx, jy) = _at(s, op.at), _at(s, op.joint)
            angle = s.drawing.joint(op.joint).slider
            dot = (jx - ax) * math.cos(angle) + (jy - ay) * math.sin(angle)
            size = math.hypot(jx - ax, jy - ay)
            if size == 0 or abs(dot) <= DEAD_RTOL * size:
                s.problems.append(Problem(("joints", op.joint), f"slider {op.joint} drawn with {op.at} -> "
                                          f"{op.joint} off the normal to its guide (the closure keeps the "
                                          "side it is drawn on)",
                                          f"{op.at} -> {op.joint} drawn normal to the guide (a dead point: "
                                          "no side)"))


def _drives(n: int) -> str:
    return f"{n} drive" if n == 1 else f"{n} drives"


def unsupported(structure: Structure, op: Group) -> str | None:
    """Why the population (drawn.population_groups) cannot solve `op` (a slider in it), or None.
    Pure Python: `check` asks it of a design file (synthesis.schema.closed_form_problem)."""
    inside = set(op.links)
    for joint, guide in structure.slides.items():
        if guide in inside or any(b in inside for b in structure.pins[joint]):
            return f"the slider {joint}"
    for joint in structure.drawing.joints:
        if joint.slider is not None and (joint.guide in inside or any(b in inside for b in structure.pins[joint.name])):
            return f"the slider {joint.name}"
    return None
