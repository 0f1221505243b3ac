"""Planar kinematic chains of pin joints with one degree of freedom, enumerated, and their
inversions, drives and targets (docs/six_bars.md). Pure Python (`check` may read it).

A chain is its link-adjacency graph: a vertex per link, an edge per pin joining two links.
With n links and j pins Gruebler's count gives the mobility F = 3 (n - 1) - 2 j, and F = 1
needs j = (3 n - 4) / 2: 4 pins for 4 links, 7 for 6. A graph is a chain of n links when it
is connected and no sub-chain is rigid: every set S of 2 to n - 1 links with the e(S) pins
among them has 3 (|S| - 1) - 2 e(S) >= 1 (a double pin between two links, a triangle, a link
with one pin would each be rigid; Tsai's "degenerate" chains). Two graphs are one chain when
they are isomorphic: the canonical form is the smallest sorted edge list over every
relabelling that numbers the links by falling degree (an isomorphism keeps degrees, so the
form is the same for isomorphic graphs and tells others apart). Six links give two chains:
Watt's (the two ternary links pinned together) and Stephenson's (apart).

An inversion grounds one link, up to the chain's automorphisms (the relabellings that keep
its edges): Watt I and II, Stephenson I, II and III. A drive is a link pinned to the ground,
turning about its pivot, up to the automorphisms that fix the ground; a target is a link
for the tracer point, the guided body (a link not pinned to the ground: the points of a
pivoted link trace circles) or the function's output (a pivoted link other than the drive),
up to the automorphisms that fix ground and drive. A target adds nothing to the four-bar
when a four-bar loop (four links, four pins: a movable sub-chain of its own) holds it
together with the ground and the drive; when such a loop holds it with the ground but not
the drive, its curve (or its poses) is a four-bar's and only its timing is the six-bar's.

Sources: L.-W. Tsai, Mechanism Design: Enumeration of Kinematic Structures According to
Function (CRC, 2001), ch. 3-4 (Gruebler's count, degenerate chains, two 1-dof chains of six
links); R. S. Hartenberg and J. Denavit, Kinematic Synthesis of Linkages (McGraw-Hill,
1964), the Watt and Stephenson chains and their five inversions; R. L. Norton, Design of
Machinery, ch. 2 (Watt I, II, Stephenson I, II, III).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from itertools import combinations, permutations, product

MAX_LINKS = 6  # the enumeration tries every set of pins: C(15, 7) = 6435 graphs for six links
FREE, TIMED = "any", "prescribed"  # a target's timing: beyond the four-bar with free timing, or only timed
TERNARY = 3

Edge = tuple[int, int]


def pins_for_one_dof(links: int) -> int:
    """j with 3 (n - 1) - 2 j = 1 (Gruebler), for an even number of links n."""
    return (3 * links - 4) // 2


def sub_chain_mobility(links: int, pins: int) -> int:
    """Gruebler's mobility 3 (n - 1) - 2 j of n links joined by j pins."""
    return 3 * (links - 1) - 2 * pins


def _masks(edges) -> list[int]:
    return [(1 << a) | (1 << b) for a, b in edges]


def is_chain(links: int, edges) -> bool:
    """Connected, every link on two pins or more, and no rigid sub-chain (module docstring)."""
    masks = _masks(edges)
    degree = [0] * links
    for a, b in edges:
        degree[a] += 1
        degree[b] += 1
    if min(degree) < 2:
        return False
    reached, frontier = 1, 1
    while frontier:
        grown = reached
        for m in masks:
            if m & reached:
                grown |= m
        frontier, reached = grown & ~reached, grown
    if reached != (1 << links) - 1:
        return False
    for size in range(2, links):
        for subset in combinations(range(links), size):
            s = sum(1 << v for v in subset)
            inside = sum(1 for m in masks if m & s == m)
            if sub_chain_mobility(size, inside) < 1:
                return False
    return True


def _degree_blocks(links: int, edges) -> list[list[int]]:
    degree = [0] * links
    for a, b in edges:
        degree[a] += 1
        degree[b] += 1
    return [[v for v in range(links) if degree[v] == d] for d in sorted(set(degree), reverse=True)]


def _relabellings(links: int, edges):
    """Every relabelling (label of each vertex) that numbers the vertices by falling degree."""
    blocks = _degree_blocks(links, edges)
    starts = [sum(len(b) for b in blocks[:i]) for i in range(len(blocks))]
    for orders in product(*(permutations(b) for b in blocks)):
        label = [0] * links
        for start, order in zip(starts, orders):
            for offset, v in enumerate(order):
                label[v] = start + offset
        yield tuple(label)


def _relabel(edges, label) -> tuple[Edge, ...]:
    return tuple(sorted((min(label[a], label[b]), max(label[a], label[b])) for a, b in edges))


def canonical(links: int, edges) -> tuple[Edge, ...]:
    """The canonical form of a graph (module docstring)."""
    return min(_relabel(edges, label) for label in _relabellings(links, edges))


@dataclass(frozen=True)
class Chain:
    """A kinematic chain: `links` links (0 .. links - 1, in canonical order) and its pins
    `edges` (pairs of links, canonical form)."""

    links: int
    edges: tuple[Edge, ...]

    def neighbours(self, v: int) -> tuple[int, ...]:
        return tuple(sorted({b if a == v else a for a, b in self.edges if v in (a, b)}))

    def degree(self, v: int) -> int:
        return len(self.neighbours(v))

    def adjacent(self, a: int, b: int) -> bool:
        return (min(a, b), max(a, b)) in self.edges

    @property
    def name(self) -> str:
        """"four-bar", "watt" (its two ternary links pinned together), "stephenson" (apart)."""
        if self.links == 4:
            return "four-bar"
        ternary = [v for v in range(self.links) if self.degree(v) == TERNARY]
        if self.links == 6 and len(ternary) == 2:
            return "watt" if self.adjacent(*ternary) else "stephenson"
        return f"{self.links}-link chain"

    def automorphisms(self) -> tuple[tuple[int, ...], ...]:
        """The relabellings that keep the edges (the identity first)."""
        edges = set(self.edges)
        return tuple(label for label in _relabellings(self.links, self.edges)
                     if set(_relabel(self.edges, label)) == edges)

    def loops4(self) -> tuple[frozenset[int], ...]:
        """The four-bar loops: sets of four links with four pins among them (each on two)."""
        return _loops4(self)


@lru_cache(maxsize=16)
def _loops4(chain: Chain) -> tuple[frozenset[int], ...]:
    out = []
    for subset in combinations(range(chain.links), 4):
        if all(sum(1 for w in subset if chain.adjacent(v, w)) == 2 for v in subset):
            out.append(frozenset(subset))
    return tuple(out)


@lru_cache(maxsize=4)
def chains(links: int) -> tuple[Chain, ...]:
    """Every 1-dof chain of `links` pinned links (an even number, 4 to MAX_LINKS), one per
    isomorphism class, in the order of their canonical forms."""
    if links % 2 or not 4 <= links <= MAX_LINKS:
        raise ValueError(f"chains of an even number of links from 4 to {MAX_LINKS}, not {links}")
    pairs = list(combinations(range(links), 2))
    forms = {canonical(links, edges) for edges in combinations(pairs, pins_for_one_dof(links))
             if is_chain(links, edges)}
    return tuple(Chain(links, form) for form in sorted(forms))


def orbit_representatives(group, items, act) -> tuple:
    """One item per orbit of `group` (relabellings) on `items`: the smallest of each orbit,
    in increasing order. act(label, item) -> the relabelled item."""
    seen, out = set(), []
    for item in sorted(items):
        if item in seen:
            continue
        orbit = {act(label, item) for label in group}
        seen |= orbit
        out.append(min(orbit))
    return tuple(out)


@dataclass(frozen=True)
class Inversion:
    """A chain with the link `ground` fixed, and its name in the literature."""

    chain: Chain
    ground: int

    @property
    def name(self) -> str:
        """four-bar; watt-i (a binary link grounded), watt-ii (a ternary); stephenson-i (a
        binary link pinned to both ternary links: both pivot on the ground), stephenson-ii (a
        binary link pinned to one ternary and one binary), stephenson-iii (a ternary)."""
        chain, g = self.chain, self.ground
        kind = chain.name
        if kind == "four-bar":
            return "four-bar"
        ternary = chain.degree(g) == TERNARY
        if kind == "watt":
            return "watt-ii" if ternary else "watt-i"
        if kind == "stephenson":
            if ternary:
                return "stephenson-iii"
            pivoted = sum(1 for v in chain.neighbours(g) if chain.degree(v) == TERNARY)
            return "stephenson-i" if pivoted == 2 else "stephenson-ii"
        return f"{kind} on link {g}"

    def stabilizer(self, *fixed: int) -> tuple[tuple[int, ...], ...]:
        """The chain's automorphisms that fix the ground and the links `fixed`."""
        keep = (self.ground,) + fixed
        return tuple(label for label in self.chain.automorphisms() if all(label[v] == v for v in keep))

    def drives(self) -> tuple[int, ...]:
        """The links pinned to the ground (each turns about its pivot), one per orbit."""
        return orbit_representatives(self.stabilizer(), self.chain.neighbours(self.ground),
                                     lambda label, v: label[v])

    def loop_with(self, *members: int) -> frozenset[int] | None:
        """The first four-bar loop holding the ground and `members`, or None."""
        need = {self.ground, *members}
        return next((loop for loop in self.chain.loops4() if need <= loop), None)

    def floating(self) -> tuple[int, ...]:
        """The links not pinned to the ground (the ground excluded)."""
        pivoted = set(self.chain.neighbours(self.ground))
        return tuple(v for v in range(self.chain.links) if v != self.ground and v not in pivoted)

    def targets(self, drive: int, task: str) -> tuple[tuple[int, str], ...]:
        """(link, timing) of every target link of `task` ("path", "motion" or "function") with
        this drive, one per orbit of the automorphisms fixing ground and drive; a link that a
        four-bar loop holds with the ground and the drive is left out (module docstring).
        timing: FREE (beyond any four-bar with free timing too) or TIMED (a four-bar's curve,
        poses or output loop, with the six-bar's timing; function generation is timed)."""
        if task == "function":
            items = [v for v in self.chain.neighbours(self.ground) if v != drive]
        elif task in ("path", "motion"):
            items = list(self.floating())
        else:
            raise ValueError(f'a task "path", "motion" or "function", not "{task}"')
        reps = orbit_representatives(self.stabilizer(drive), items, lambda label, v: label[v])
        out = []
        for v in reps:
            if self.chain.links > 4 and self.loop_with(drive, v) is not None:
                continue  # the four-bar ground-drive-...-v moves it alone
            timed = task == "function" or (self.chain.links > 4 and self.loop_with(v) is not None)
            out.append((v, TIMED if timed else FREE))
        return tuple(out)


@lru_cache(maxsize=4)
def inversions(links: int) -> tuple[Inversion, ...]:
    """Every inversion of the 1-dof chains of `links` links, one per ground orbit."""
    out = []
    for chain in chains(links):
        for g in orbit_representatives(chain.automorphisms(), range(chain.links), lambda label, v: label[v]):
            out.append(Inversion(chain, g))
    return tuple(out)
