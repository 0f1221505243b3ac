"""Typed, error-collecting access to a parsed TOML file, with the line of every key.

A `Reader` parses the text with tomllib and finds key lines by a scan of the raw text
(a key inside an inline table or array resolves to the line of its parent; a line that
cannot be found is left out rather than guessed). A `Table` hands out checked values
and records every error instead of raising, so that one run reports all the problems of
a file; `Reader.finish()` adds the unknown keys (with a "did you mean" hint) and raises
them all together as `InputErrors`. No numerics here.
"""

from __future__ import annotations

import difflib
import heapq
import math
import re
import tomllib
from typing import NamedTuple

from linkcli.errors import MAX_LISTED, InputError, InputErrors, SchemaError, TomlSyntaxError
from linkcli.io.header_lines import with_parent_lines
from linkcli.io.huge_numbers import refuse_huge_integers, too_many_digits
from linkcli.io.link_names import link_name_hint
from linkcli.io.misplaced_keys import top_level_hint
from linkcli.io.nesting import MAX_DEPTH, deep_bracket_line, deep_key_line, too_deep
from linkcli.io.safe_read import read_problem_bytes
from linkcli.io.terminal_text import one_line as _one_line  # escaped, one line (bounded by errors.InputError)

MISSING = object()
MAX_ARRAY = 10_000  # longest array accepted anywhere in a problem file

_PART = r"""(?:[A-Za-z0-9_\-]+|"[^"]*"|'[^']*')"""
_DOTTED = rf"{_PART}(?:\s*\.\s*{_PART})*"
_HEADER = re.compile(r"^\s*\[\[?\s*([^\]]+?)\s*\]\]?\s*(#.*)?$")
_KEY = re.compile(rf"^\s*({_DOTTED})\s*=")
_INLINE_KEY = re.compile(rf"[{{,]\s*({_DOTTED})\s*=")


def _split_key(text: str) -> list[str]:
    """The parts of a (dotted) key as written; a quoted part with an escape is decoded
    by tomllib itself."""
    if "\\" in text:
        try:
            node, parts = tomllib.loads(f"{text} = 0"), []
            while isinstance(node, dict) and len(node) == 1:
                key, node = next(iter(node.items()))
                parts.append(key)
            return parts
        except tomllib.TOMLDecodeError:
            pass
    parts = re.findall(r"""[A-Za-z0-9_\-]+|"[^"]*"|'[^']*'""", text)
    return [p.strip("\"'") for p in parts]


def describe(value) -> str:
    """A found value as the user wrote it, with its TOML type."""
    if value is MISSING:
        return "nothing (the key is missing)"
    if isinstance(value, bool):
        return f"{str(value).lower()} (boolean)"
    if isinstance(value, (int, float)):
        text = repr(value)
        if isinstance(value, float) and not math.isfinite(value):
            text = "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
        return text
    if isinstance(value, str):  # a long one is cut where the error is made (errors.InputError)
        return f'"{_one_line(value)}" (string)'
    if isinstance(value, list):
        text = _short_literal(value)
        return f"an array of {len(value)}" + (f": {text}" if text and value else "")
    if isinstance(value, dict):
        return "a table"
    return type(value).__name__


def _short_literal(value, depth: int = 0) -> str | None:
    """A small array of numbers, booleans or short strings (or arrays of them, two levels)
    as written in TOML (`[inf, 0]`, `[[0, 0], [1, 1]]`), or None when it would not be
    short: the found value of an error names what is wrong in it."""
    if isinstance(value, list):
        if depth >= 2 or len(value) > 6:
            return None
        parts = [_short_literal(v, depth + 1) for v in value]
        text = None if None in parts else "[" + ", ".join(parts) + "]"
        return text if text is not None and len(text) <= 60 else None
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, (int, float)):
        return describe(value) if not isinstance(value, int) or abs(value) < 10**15 else None
    if isinstance(value, str) and len(value) <= 20:
        return '"' + _one_line(value) + '"'
    return None


_OUTSIDE = re.compile(r"[\n#\"']")  # what can change the state outside a string
_IN_BASIC = re.compile(r'[\n"\\]')
_IN_LITERAL = re.compile(r"[\n']")


def _mask(text: str) -> tuple[str, set[int]]:
    """The text with every string's content replaced by "x" and every comment by blanks
    (same length, newlines kept), and the 1-based lines that begin inside a multi-line
    string. TOML 1.0 strings: basic "..." (backslash escapes), literal '...', multi-line
    basic \"\"\"...\"\"\" (escapes, a line-ending backslash) and multi-line literal '''...''';
    a multi-line string closes at the last quote of a run of three to five quotes (up to two
    quotes may stand next to the closing delimiter). `#` outside a string opens a comment
    to the end of the line. The text is valid TOML (tomllib has parsed it)."""
    blanks: list[tuple[int, int, str]] = []  # (start, end, fill) spans to overwrite
    inside: set[int] = set()
    n, i, line = len(text), 0, 1
    while True:
        m = _OUTSIDE.search(text, i)
        if m is None:
            break
        i, ch = m.start(), m.group()
        if ch == "\n":
            line += 1
            i += 1
            continue
        if ch == "#":
            stop = text.find("\n", i)
            stop = n if stop < 0 else stop
            blanks.append((i, stop, " "))
            i = stop
            continue
        multi = text.startswith(ch * 3, i)
        i += 3 if multi else 1
        begin = i
        scan = _IN_BASIC if ch == '"' else _IN_LITERAL
        while True:
            m = scan.search(text, i)
            if m is None:  # cannot happen in valid TOML
                i = n
                break
            i, c = m.start(), m.group()
            if c == "\n":
                line += 1
                inside.add(line)
                i += 1
            elif c == "\\":  # an escape: the next character is content (or a line end)
                i += 1 if text.startswith("\n", i + 1) else 2
            elif not multi:
                break
            else:
                run = 1
                while i + run < n and text[i + run] == ch:
                    run += 1
                if run >= 3:
                    i += run - 3
                    break
                i += run
        blanks.append((begin, i, "x"))
        i += 3 if multi else 1
    if not blanks:
        return text, inside
    parts, last = [], 0
    for a, b, fill in blanks:
        parts.append(text[last:a])
        seg = text[a:b]
        parts.append("\n".join(fill * len(piece) for piece in seg.split("\n")))
        last = b
    parts.append(text[last:])
    return "".join(parts), inside


def _line_map(text: str, masked: tuple[str, set[int]] | None = None) -> dict[tuple[str, ...], int]:
    """Key path -> 1-based line, from a scan of the raw text.

    Structure (headers, keys, brackets) is read from the masked text of `_mask`, so that
    a `#`, a bracket or a `key =` inside a string or a comment counts for nothing; key
    names are then taken from the raw text at the same place (quoted keys keep their
    content). A line that begins inside a multi-line string holds no key. `masked`: the
    text's `_mask` when the caller has it."""
    masked, inside = masked or _mask(text)
    lines: dict[tuple[str, ...], int] = {}
    twice: set[tuple[str, ...]] = set()  # paths met on two lines: array-of-tables elements

    def put(path: tuple[str, ...], n: int) -> None:
        if lines.setdefault(path, n) != n:
            twice.add(path)

    table: tuple[str, ...] = ()
    depth = 0  # open brackets of a multi-line array: keys inside belong to its key
    elements: dict[tuple[str, ...], int] = {}  # [[array]] headers met so far
    raw_lines = text.split("\n")
    for n, line in enumerate(masked.split("\n"), start=1):
        raw = raw_lines[n - 1]
        if depth == 0 and n not in inside:
            m = _HEADER.match(line)
            if m:
                table = tuple(_split_key(raw[m.start(1):m.end(1)]))
                put(table, n)
                if line.lstrip().startswith("[["):  # an element of an array of tables: its keys
                    k = elements[table] = elements.get(table, -1) + 1  # also as "name[k]"
                    table = table[:-1] + (f"{table[-1]}[{k}]",)
                    put(table, n)
                continue
            m = _KEY.match(line)
            if m:
                path = table + tuple(_split_key(raw[m.start(1):m.end(1)]))
                put(path, n)
                rest = line[m.end():]
                for k in _INLINE_KEY.finditer(rest):
                    put(path + tuple(_split_key(raw[m.end() + k.start(1):m.end() + k.end(1)])), n)
                depth = max(0, rest.count("[") - rest.count("]"))
                continue
        else:
            depth = max(0, depth + line.count("[") - line.count("]"))
    for path in twice:  # which element a key belongs to is not known here: no line
        del lines[path]
    return with_parent_lines(lines, twice)



def _last_line(text: str) -> int:
    """The last line of a text as an editor numbers it (a final newline opens no line of
    its own): where a syntax error "at end of document" is, e.g. a file ending in `x = `
    or in an unclosed `[table` or array."""
    return max(1, text.count("\n") + (0 if text.endswith("\n") else 1))


def _key_at(lines: dict[tuple[str, ...], int], line: int | None) -> str | None:
    """The key whose value holds `line`: the first key of the nearest line at or above it
    (an array's value may run over several lines), dotted; None if there is none."""
    best, where = None, 0
    for path, n in lines.items():
        if line is not None and where < n <= line:
            best, where = path, n
    return _one_line(".".join(best)) if best else None


def _kind(positive: bool, nonnegative: bool, integer: bool) -> str:
    """What a number must be, in words."""
    if positive:
        return "a positive integer" if integer else "a positive number"
    if nonnegative:
        return "a non-negative integer" if integer else "a number >= 0"
    return "an integer" if integer else "a number"


_STATES_RANGE = re.compile(r"\bin [\[(]|\d to [-+]?\d|magnitude")  # a `what` that words its own range


class NumberRule(NamedTuple):
    """What a number in the file must be: finite (never a bool), and optionally positive,
    non-negative, an integer, within [lo, hi]; `what` words it instead of the default."""

    positive: bool = False
    nonnegative: bool = False
    integer: bool = False
    lo: float | None = None
    hi: float | None = None
    what: str | None = None

    @property
    def expected(self) -> str:
        """The `expected` of the error: its words, and the range when there is one."""
        kind = self.what or _kind(self.positive, self.nonnegative, self.integer)
        states_range = self.what is not None and _STATES_RANGE.search(self.what) is not None  # its words give
        # the bounds ("a fraction ... in (0, 2]", "of magnitude 1e-09 to 1e+09"): not said twice
        if (self.lo is not None or self.hi is not None) and not states_range:
            hi = "inf" if self.hi is None else _fmt(self.hi)
            if self.positive and (self.lo is None or self.lo <= 0):  # a positive number's range opens at 0
                kind += f" in (0, {hi}]"
            elif self.nonnegative and (self.lo is None or self.lo < 0):
                kind += f" in [0, {hi}]"
            else:
                kind += f" in [{'-inf' if self.lo is None else _fmt(self.lo)}, {hi}]"
        return kind

    def accepts(self, value) -> bool:
        if (isinstance(value, bool) or not isinstance(value, (int, float))
                or (self.integer and not isinstance(value, int))
                or (isinstance(value, float) and not math.isfinite(value))):
            return False
        v = int(value) if self.integer else float(value)
        return not ((self.positive and v <= 0) or (self.nonnegative and v < 0)
                    or (self.lo is not None and v < self.lo) or (self.hi is not None and v > self.hi))

class Reader:
    """One problem file: its data, its key lines, and the errors found so far. `text` is
    the file's content when the caller has it (str, or the file's bytes as read elsewhere,
    e.g. by a `--cluster` client for a worker without the file); None reads `path`."""

    def __init__(self, path: str, text: str | bytes | None = None) -> None:
        self.path = path
        self.errors: list[InputError] = []
        self._seen: dict[tuple[str, ...], set[str]] = {}
        self._tables: dict[tuple[str, ...], dict] = {}
        self._expected: list[tuple[tuple[str, ...], dict, frozenset]] = []  # tables of a fixed vocabulary
        if text is None:
            text = read_problem_bytes(path)
        if isinstance(text, bytes):
            raw = text
            try:
                text = raw.decode("utf-8")
            except UnicodeDecodeError as exc:
                raise InputError("a UTF-8 text file", f"an undecodable byte at offset {exc.start}", path=path) from None
        if text.startswith("\ufeff"):  # a UTF-8 byte-order mark (Windows editors): not TOML
            text = text[1:]
        masked = _mask(text)
        deep = deep_key_line(masked[0])
        if deep is not None:  # before tomllib, whose parse is quadratic in a key's parts
            raise SchemaError(f"dotted keys of at most {MAX_DEPTH} parts",
                              "a longer one", path=path, line=deep)
        try:
            self.data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            msg = str(exc)
            m = re.search(r"\(at line (\d+), column (\d+)\)", msg)
            line = int(m.group(1)) if m else _last_line(text) if "(at end of document)" in msg else None
            msg = re.sub(r"\s*\(at line \d+, column \d+\)", "", msg)
            if m:
                msg += f" (column {m.group(2)})"
            msg = "a syntax error: " + msg[:1].lower() + msg[1:]
            if text.lstrip().startswith(("{", "[{")) or str(path).lower().endswith(".json"):
                msg += " (a JSON file? linkcli reads TOML: a result to analyse is written with --format toml)"
            raise TomlSyntaxError("valid TOML", msg, path=path, line=line) from None
        except ValueError:  # not a TOMLDecodeError: an integer beyond Python's digit limit
            error = too_many_digits(path, text)
            error.key = _key_at(_line_map(text, masked), error.line)
            raise error from None
        except RecursionError:
            raise SchemaError(f"tables and arrays nested at most {MAX_DEPTH} levels deep",
                              "deeper nesting", path=path, line=deep_bracket_line(masked[0])) from None
        self.lines = _line_map(text, masked)
        deep = too_deep(self.data)
        if deep is not None:
            self.error(deep, f"tables and arrays nested at most {MAX_DEPTH} levels deep",
                       raw_got="deeper nesting")
            raise InputErrors(self.errors)
        refuse_huge_integers(self)

    # -- errors ---------------------------------------------------------------
    def line_of(self, path: tuple[str, ...]) -> int | None:
        line = self.lines.get(path)
        if line is not None:  # a key on a line of its own (the usual case)
            return line
        if any("[" in p for p in path):
            for n in range(len(path), 0, -1):  # in an element of an array of tables: `name[k]` (_line_map)
                if path[:n] in self.lines and any(re.search(r"\[\d+\]$", p) for p in path[:n]):
                    return self.lines[path[:n]]
            path = tuple(re.sub(r"\[\d+\]$", "", p) for p in path)  # an array item `key[i]`: its key's line
        for n in range(len(path), 0, -1):
            if path[:n] in self.lines:
                return self.lines[path[:n]]
        return None

    def error(self, path: tuple[str, ...], expected: str, got=MISSING, *, raw_got: str | None = None) -> None:
        found = _one_line(raw_got) if raw_got is not None else describe(got)
        line = self.line_of(path)
        if line is None and got is MISSING and raw_got is None:
            line = self._missing_line(path)
        self.errors.append(SchemaError(expected, found, path=self.path, line=line,
                                       key=_one_line(".".join(path)) or None))

    def _missing_line(self, path: tuple[str, ...]) -> int | None:
        """The line of a missing key that has no table line to fall back on: line 1 when
        what is missing is a top-level key or table (the file has no line of it: the top
        level starts at line 1); None when a table above it exists on no line this reader
        knows (an element of an array of tables it cannot tell apart: not guessed)."""
        return 1 if path and path[0] not in self.data else None

    def table(self, name: str | tuple[str, ...], required: bool = False) -> Table | None:
        path = (name,) if isinstance(name, str) else tuple(name)
        node = self.data
        for part in path:
            if not isinstance(node, dict) or part not in node:
                if required:
                    self.error(path, "a table")
                return None
            node = node[part]
        if not isinstance(node, dict):
            self.error(path, "a table", node)
            return None
        return Table(self, path, node)

    def root(self) -> Table:
        return Table(self, (), self.data)

    def mark(self, path: tuple[str, ...], key: str) -> None:
        self._seen.setdefault(path, set()).add(key)
        self._tables.setdefault(path, {})

    def register(self, path: tuple[str, ...], data: dict) -> None:
        self._tables[path] = data
        self._seen.setdefault(path, set())

    def expect(self, path: tuple[str, ...], data: dict, keys: frozenset) -> None:
        """A table whose keys are a fixed vocabulary, `keys` (a result file's output
        section, judged by what the report writer writes): its other keys are unknown keys
        for finish(), reported as any table's. `keys` is shared, not copied: the 100,000
        rows of a motion study cost a tuple each."""
        self._expected.append((path, data, keys))

    def finish(self) -> None:
        """Report unknown keys of every table read, then raise everything collected, in
        the order of their lines (at most MAX_LISTED listed: InputErrors). Linear in the
        number of keys: the message of an unknown key (its "did you mean") is built only
        for the keys listed."""
        unknown = []  # (path, key, allowed) of each unknown key
        for path, data in self._tables.items():
            allowed = self._allowed.get(path, set()) | self._seen.get(path, set())
            unknown.extend((path, key, allowed) for key in data if key not in allowed)
        for path, data, allowed in self._expected:
            unknown.extend((path, key, allowed) for key in data if key not in allowed)
        if not self.errors and not unknown:
            return
        # by line; on one line, the checks' errors before the unknown keys; one line per key (a
        # value two checks judge, a result's nan: "a finite number", then "a number": the first)
        once, seen = [], set()
        for e in self.errors:
            at = (e.line, getattr(e, "key", None))
            if at[1] is None or at not in seen:
                once.append(e)
                seen.add(at)
        entries = [(e.line or 0, i, e) for i, e in enumerate(once)]
        entries += [(self.line_of(path + (key,)) or 0, len(entries) + j, (path, key, allowed))
                    for j, (path, key, allowed) in enumerate(unknown)]
        listed = heapq.nsmallest(MAX_LISTED, entries)
        top_level = self._tables.get((), {}).keys() | self._seen.get((), set())
        known: dict[tuple[str, ...], list[str]] = {}  # a table's known keys, sorted once
        errors = []
        for line, _, item in listed:
            if isinstance(item, InputError):
                errors.append(item)
                continue
            path, key, allowed = item
            names = known.setdefault(path, sorted(allowed))
            errors.append(SchemaError(_unknown_key_expected(path, key, allowed, names, top_level),
                                      _one_line(f'unknown key "{key}"'), path=self.path, line=line or None,
                                      key=_one_line(".".join(path + (key,))) or None))
        raise InputErrors(errors, unlisted=len(entries) - len(listed))

    @property
    def _allowed(self) -> dict[tuple[str, ...], set[str]]:
        return getattr(self, "_allowed_keys", {})

    def allow(self, path: tuple[str, ...], keys) -> None:
        """Declare keys a table may hold without having been read (optional, skipped)."""
        if not hasattr(self, "_allowed_keys"):
            self._allowed_keys = {}
        self._allowed_keys.setdefault(path, set()).update(keys)


def _unknown_key_expected(path: tuple[str, ...], key: str, allowed: set[str], known: list[str],
                          top_level) -> str:
    """The `expected` of an unknown key: a "did you mean" among the table's `known` keys
    (sorted), else the list of them; a textbook link name's key; a top-level key written
    under a [table] header."""
    hint = difflib.get_close_matches(key, known, n=1, cutoff=0.6)
    expected = "a known key" + (f' (did you mean "{hint[0]}"?)' if hint
                                else f" (one of: {', '.join(known)})" if known else "")
    expected = link_name_hint(key, allowed) or expected
    return top_level_hint(path, key, top_level) or expected


class Table:
    """Checked access to one TOML table; every accessor records its key as known."""

    def __init__(self, reader: Reader, path: tuple[str, ...], data: dict) -> None:
        self.reader = reader
        self.path = path
        self.data = data
        reader.register(path, data)

    def __contains__(self, key: str) -> bool:
        return key in self.data

    def keys(self):
        return self.data.keys()

    def raw(self, key: str, default=MISSING):
        self.reader.mark(self.path, key)
        return self.data.get(key, default)

    def error(self, key: str | None, expected: str, got=MISSING, **kw) -> None:
        self.reader.error(self.path + ((key,) if key else ()), expected, got, **kw)

    def allow(self, *keys: str) -> None:
        self.reader.allow(self.path, keys)

    def table(self, key: str, required: bool = False) -> Table | None:
        value = self.raw(key)
        if value is MISSING:
            if required:
                self.error(key, "a table")
            return None
        if not isinstance(value, dict):
            self.error(key, "a table", value)
            return None
        return Table(self.reader, self.path + (key,), value)

    # -- scalars ----------------------------------------------------------------
    def _absent(self, key: str, default, expected: str):
        """A missing key: its default, or None after recording that `expected` is missing."""
        if default is MISSING:
            self.error(key, expected)
            return None
        return default

    def number(self, key: str, default=MISSING, *, positive: bool = False, nonnegative: bool = False,
               integer: bool = False, lo: float | None = None, hi: float | None = None,
               what: str | None = None):
        """A finite number (bool rejected); None when missing or bad (error recorded)."""
        value = self.raw(key)
        if value is MISSING:
            return self._absent(key, default, f"{what or _kind(positive, nonnegative, integer)}")
        return self.check_number(key, value, NumberRule(positive, nonnegative, integer, lo, hi, what))

    def check_number(self, key, value, rule: NumberRule, index: int | None = None):
        """`value` as the rule's number (int or float); None after recording the error
        (at `key[index]` for an array's item)."""
        fullkey = key if index is None else f"{key}[{index}]"
        if rule.accepts(value):
            return int(value) if rule.integer else float(value)
        self.reader.error(self.path + (fullkey,), rule.expected, value)
        return None

    def string(self, key: str, default=MISSING, choices: tuple[str, ...] | None = None,
               max_len: int = 2000):
        value = self.raw(key)
        if value is MISSING:
            return self._absent(key, default, f"one of: {', '.join(choices)}" if choices else "a string")
        if not isinstance(value, str) or len(value) > max_len:
            self.error(key, f"one of: {', '.join(choices)}" if choices
                       else f"a string of at most {max_len} characters", value)
            return None
        if choices is not None and value not in choices:
            hint = difflib.get_close_matches(value, choices, n=1, cutoff=0.6)
            extra = f' (did you mean "{hint[0]}"?)' if hint else ""
            self.error(key, f"one of: {', '.join(choices)}{extra}", value)
            return None
        return value

    def _of_type(self, key: str, default, kind: type, expected: str):
        """The value of `key` when it is a `kind`; a missing key's default; else None after
        recording the error."""
        value = self.raw(key)
        if value is MISSING:
            return self._absent(key, default, expected)
        if not isinstance(value, kind):
            self.error(key, expected, value)
            return None
        return value

    def boolean(self, key: str, default=MISSING):
        return self._of_type(key, default, bool, "true or false")

    def number_list(self, key: str, default=MISSING, *, min_len: int = 1, max_len: int = MAX_ARRAY,
                    length: int | None = None, positive: bool = False, what: str = "numbers"):
        """An array of finite numbers; None when missing or bad."""
        value = self.raw(key)
        if value is MISSING:
            return self._absent(key, default, f"an array of {what}")
        want = (f"an array of {length} {what}" if length is not None
                else f"an array of {min_len} to {max_len} {what}")
        if not isinstance(value, list) or (length is not None and len(value) != length) or not (min_len <= len(value) <= max_len):
            self.error(key, want, value)
            return None
        out = []
        rule = NumberRule(positive=positive, what=f"a {'positive ' if positive else ''}number")
        for i, item in enumerate(value):
            v = self.check_number(key, item, rule, index=i)
            if v is None:
                return None
            out.append(v)
        return out

    def range(self, key: str, default=MISSING, *, positive: bool = False, nonnegative: bool = False):
        """A bound: a number (fixed value) or [lo, hi] with lo <= hi; returns (lo, hi)."""
        value = self.raw(key)
        if value is MISSING:
            return self._absent(key, default, "a number or a range [lo, hi]")
        if isinstance(value, list):
            nums = self.number_list(key, length=2, positive=positive)
            if nums is None:
                return None
            lo, hi = nums
            if nonnegative and lo < 0:
                self.error(key, "a range with lo >= 0", value, raw_got=f"[{_fmt(lo)}, {_fmt(hi)}]")
                return None
            if lo > hi:
                self.error(key, "a range [lo, hi] with lo <= hi", raw_got=f"[{_fmt(lo)}, {_fmt(hi)}]")
                return None
            return (lo, hi)
        v = self.check_number(key, value, NumberRule(positive, nonnegative, what="a number or a range [lo, hi]"))
        return None if v is None else (v, v)

    def point_range(self, key: str, default=MISSING):
        """A bound on a point: `{ x = ..., y = ... }`, each coordinate a number (fixed) or a
        range [lo, hi]; returns ((x_lo, x_hi), (y_lo, y_hi)), or None (error recorded)."""
        value = self._of_type(key, default, dict, "a table { x = ..., y = ... } (each a number or a range [lo, hi])")
        if key not in self or value is None:  # missing (its default) or not a table
            return value
        sub = self.table(key)
        xr = sub.range("x")
        yr = sub.range("y")
        if xr is None or yr is None:
            return None
        return (xr, yr)


def _fmt(x: float) -> str:
    return repr(int(x)) if float(x).is_integer() else repr(float(x))
