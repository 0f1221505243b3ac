"""What a result file holds beyond what `analyze` reads back: checked, never ignored.

A result file is linkcli's own output (`synth --format toml`), so what it may hold is
known: the report's top-level keys (`top_keys`), a `type` and `status` of their
vocabularies, strings where the report writes strings, numbers that are finite (the
writer leaves a non-finite number out: TOML has no null) in arrays no longer than a
problem file's (or, for the rows of a motion study, its `steps`), and in every output
section ([transmission], [error], [solver], the rows of [[kinematics]], [tolerance] and
its tables, a type's own sections, ...) the keys the report writer writes there
(`reading.result_keys`, found by running the writer: tests/result_keys_corpus.py), a map keyed
by the linkage's own names (pins, links, joints) taking any name. Anything else is an
error on its own line, like an unknown key of a problem file. The sections `analyze`
reads (READ: [units], [linkage], [motion]'s study, [loads], [masses]) are checked key by
key where they are read.
"""

from __future__ import annotations

import math
from functools import lru_cache

from linkcli.reading.meta import ALL_SECTIONS
from linkcli.io.reader import MAX_ARRAY, Table
from linkcli.reading.result_keys import KEYS, OPEN, ROWS
from linkcli.registry import NAMES, problem_type

STATUSES = ("ok", "infeasible", "not-converged")
MAX_STEPS = 100_000  # [motion] steps: a motion study's rows (kinematics, forces.rows, ...)
MAX_VALUE_ERRORS = 100  # a file of garbage: the first ones are enough
READ = ("units", "linkage", "motion", "loads", "masses")  # read back by result_file.parse
_REPORT_KEYS = ("file", "title", "type", "status", "message", "units", "notes", "linkage",
                "loads", "masses")


@lru_cache(maxsize=None)
def top_keys() -> tuple[str, ...]:
    """Every top-level key a result file of any type may hold: the report's own, every
    section a type can be asked for, and every section the writer writes (reading.result_keys:
    a type's own sections, its solver's Solution.sections)."""
    typed = (s for name in NAMES for s in problem_type(name).sections)
    return tuple(dict.fromkeys((*_REPORT_KEYS, *ALL_SECTIONS, *typed, *KEYS)))


def check_header(root: Table) -> bool:
    """`type` (one of the problem types), `status`, and the strings `file`, `title`,
    `message`, `notes`; True when `type` is good (the rest can then be judged)."""
    kind = root.string("type", choices=NAMES)
    root.string("status", choices=STATUSES)
    for key in ("file", "title", "message"):
        root.string(key, None)
    notes = root.raw("notes", None)
    if notes is not None and not (isinstance(notes, list) and len(notes) <= MAX_ARRAY
                                  and all(isinstance(n, str) for n in notes)):
        root.error("notes", f"an array of at most {MAX_ARRAY} strings", notes)
    root.allow(*top_keys())
    return kind is not None


def row_cap(root: Table) -> int:
    """The longest array a result may hold: a problem file's cap, or the `steps` of its
    motion study (one row each) when larger."""
    motion = root.data.get("motion")
    steps = motion.get("steps") if isinstance(motion, dict) else None
    ok = isinstance(steps, int) and not isinstance(steps, bool) and 2 <= steps <= MAX_STEPS
    return max(MAX_ARRAY, steps) if ok else MAX_ARRAY


def check_values(root: Table) -> None:
    """Every number in the file finite and every array at most `row_cap` long: one located
    error per bad value (at most MAX_VALUE_ERRORS)."""
    cap, found, known = row_cap(root), 0, top_keys()
    stack = [((k,), v) for k, v in reversed(root.data.items()) if k in known]  # unknown: one line
    while stack and found < MAX_VALUE_ERRORS:
        path, value = stack.pop()
        if isinstance(value, float) and not math.isfinite(value):
            root.reader.error(path, "a finite number (a result file holds no nan or inf)", value)
            found += 1
        elif isinstance(value, list) and len(value) > cap:
            root.reader.error(path, f"an array of at most {cap} elements",
                              raw_got=f"an array of {len(value)} elements")
            found += 1
        elif isinstance(value, list):
            head, last = path[:-1], path[-1]
            stack.extend((head + (f"{last}[{i}]",), v) for i, v in reversed(list(enumerate(value))))
        elif isinstance(value, dict):
            stack.extend((path + (k,), v) for k, v in reversed(list(value.items())))


@lru_cache(maxsize=None)
def key_tree(section: str) -> dict:
    """The keys the writer writes in `section` as a tree (reading.result_keys: dotted paths):
    {key: subtree}, {} under a value; ROWS: the rows of an array of tables; OPEN: a map of
    the linkage's own names. Each table's keys are a frozenset under the key None (no
    TOML key: shared by every row judged by them)."""
    tree: dict = {}
    for path in KEYS.get(section, ()):
        node = tree
        for part in path.split("."):
            node = node.setdefault(part, {})
    return _frozen(tree)


def _frozen(tree: dict) -> dict:
    out = {key: _frozen(sub) for key, sub in tree.items()}
    if tree:
        out[None] = frozenset(key for key in tree if key not in (ROWS, OPEN))
    return out


def check_sections(root: Table) -> None:
    """Every key of the output sections (all but READ) one the report writer writes there:
    an unknown key is an error on its line (Reader.expect, reported by Reader.finish as an
    unknown key of a problem file, with its "did you mean")."""
    for section, value in root.data.items():
        if section in KEYS and section not in READ:
            _judge(root.reader, (section,), value, key_tree(section))


def _judge(reader, path: tuple[str, ...], value, tree: dict) -> None:
    """`value` at `path` against its key tree; iterative over rows (100,000 of them). A table
    where the writer writes a value (a number, a string, an array of numbers), and a value
    or an array of tables where it writes a table, is an error on its line: the writer never
    writes one (a table inserted into a row of [[kinematics]] analysed without a word)."""
    stack = [(path, value, tree)]
    while stack:
        path, value, tree = stack.pop()
        if isinstance(value, list):  # rows: each judged by the keys of ROWS
            rows = tree.get(ROWS)
            if rows:
                head, last = path[:-1], path[-1]
                stack.extend((head + (f"{last}[{i}]",), item, rows) for i, item in enumerate(value)
                             if isinstance(item, dict))
            elif any(isinstance(item, dict) for item in value):
                reader.error(path, "a value as linkcli writes it there (a number, a string or an array "
                             "of numbers)", raw_got="an array of tables")
        elif isinstance(value, dict) and tree:
            if OPEN in tree:  # a map of names: any name, each judged by the same keys
                stack.extend((path + (name,), item, tree[OPEN]) for name, item in value.items())
                continue
            reader.expect(path, value, tree[None])
            stack.extend((path + (key,), item, tree[key]) for key, item in value.items()
                         if key in tree)
        elif isinstance(value, dict):  # a table where the writer writes a value
            reader.error(path, "a value as linkcli writes it there (a number, a string or an array "
                         "of numbers), not a table", raw_got=f"a table of {len(value)} key"
                         + ("" if len(value) == 1 else "s"))
        elif tree and not (set(tree) - {None}) <= {ROWS, OPEN}:
            reader.error(path, "a table as linkcli writes it there (of the keys "
                         f"{', '.join(sorted(k for k in tree if k not in (None, ROWS, OPEN)))[:200]})",
                         value)
