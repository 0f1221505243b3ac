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
import math
import re
import tomllib
from typing import NamedTuple

from linkcli.errors import InputError, InputErrors, SchemaError, TomlSyntaxError
from linkcli.io.safe_read import read_problem_bytes
from linkcli.io.terminal_text import shown as _one_line  # escaped, one line, at most 200 characters
from linkcli.io.misplaced_keys import top_level_hint
from linkcli.io.link_names import link_name_hint
from linkcli.io.header_lines import with_parent_lines
from linkcli.io.huge_numbers import refuse_huge_integers, too_many_digits

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
    if isinstance(value, str):
        short = value if len(value) <= 60 else value[:57] + "..."
        return f'"{_one_line(short)}" (string)'
    if isinstance(value, list):
        return f"an array of {len(value)}"
    if isinstance(value, dict):
        return "a table"
    return type(value).__name__


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


def _line_map(text: str) -> dict[tuple[str, ...], int]:
    """Key path -> 1-based line, from a scan of the raw text.

    Structure (headers, keys, brackets) is read from the masked text of `_mask`, so that
    a `#`, a bracket or a `key =` inside a string or a comment counts for nothing; key
    names are then taken from the raw text at the same place (quoted keys keep their
    content). A line that begins inside a multi-line string holds no key."""
    masked, inside = _mask(text)
    lines: dict[tuple[str, ...], int] = {}
    twice: set[tuple[str, ...]] = set()  # paths met on two lines: array-of-tables elements

    def put(path: tuple[str, ...], n: int) -> None:
        if lines.setdefault(path, n) != n:
            twice.add(path)

    table: tuple[str, ...] = ()
    element: tuple[str, ...] | None = None  # [[a.b]]: ("a", "b[i]"), the i-th element's own path
    elements: dict[tuple[str, ...], int] = {}
    depth = 0  # open brackets of a multi-line array: keys inside belong to its key
    raw_lines = text.split("\n")
    for n, line in enumerate(masked.split("\n"), start=1):
        raw = raw_lines[n - 1]
        if depth == 0 and n not in inside:
            m = _HEADER.match(line)
            if m:
                table = tuple(_split_key(raw[m.start(1):m.end(1)]))
                put(table, n)
                element = None
                if line.lstrip().startswith("[["):
                    index = elements[table] = elements.get(table, -1) + 1
                    element = table[:-1] + (f"{table[-1]}[{index}]",)
                    put(element, n)
                continue
            m = _KEY.match(line)
            if m:
                key = tuple(_split_key(raw[m.start(1):m.end(1)]))
                path = table + key
                put(path, n)
                rest = line[m.end():]
                for k in _INLINE_KEY.finditer(rest):
                    put(path + tuple(_split_key(raw[m.end() + k.start(1):m.end() + k.end(1)])), n)
                if element is not None:
                    put(element + key, n)
                depth = max(0, rest.count("[") - rest.count("]"))
                continue
        else:
            depth = max(0, depth + line.count("[") - line.count("]"))
    for path in twice:  # which element a key belongs to is not known here: no line
        del lines[path]
    return with_parent_lines(lines, twice)



def _kind(positive: bool, nonnegative: bool, integer: bool) -> str:
    """What a number must be, in words."""
    if positive:
        return "a positive integer" if integer else "a positive number"
    if nonnegative:
        return "a non-negative integer" if integer else "a number >= 0"
    return "an integer" if integer else "a number"


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
        if self.lo is not None or self.hi is not None:
            kind += f" in [{'-inf' if self.lo is None else _fmt(self.lo)}, {'inf' if self.hi is None else _fmt(self.hi)}]"
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
        try:
            self.data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            msg = str(exc)
            m = re.search(r"\(at line (\d+), column (\d+)\)", msg)
            line = int(m.group(1)) if m else None
            msg = re.sub(r"\s*\(at line \d+, column \d+\)", "", msg)
            if m:
                msg += f" (column {m.group(2)})"
            msg = "a syntax error: " + msg[:1].lower() + msg[1:]
            raise TomlSyntaxError("valid TOML", msg, path=path, line=line) from None
        except ValueError:  # not a TOMLDecodeError: an integer beyond Python's digit limit
            raise too_many_digits(path, text) from None
        except RecursionError:
            raise TomlSyntaxError("valid TOML", "nesting too deep", path=path) from None
        self.lines = _line_map(text)
        refuse_huge_integers(self)

    # -- errors ---------------------------------------------------------------
    def line_of(self, path: tuple[str, ...]) -> int | None:
        """The line of a key path, or of its nearest parent found; "name[i]" is the i-th
        element of an array of tables ([[name]]), else an item of an array (its key's line)."""
        exact = tuple(path)
        path = tuple(re.sub(r"\[\d+\]$", "", p) for p in path)
        for n in range(len(path), 0, -1):
            for candidate in (exact[:n], path[:n]):
                if candidate in self.lines:
                    return self.lines[candidate]
        return None

    def error(self, path: tuple[str, ...], expected: str, got=MISSING, *, raw_got: str | None = None) -> None:
        found = _one_line(raw_got) if raw_got is not None else describe(got)
        self.errors.append(SchemaError(expected, found, path=self.path, line=self.line_of(path),
                                       key=_one_line(".".join(path)) or None))

    def table(self, name: str | tuple[str, ...], required: bool = False) -> "Table | None":
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

    def root(self) -> "Table":
        return Table(self, (), self.data)

    def mark(self, path: tuple[str, ...], key: str) -> None:
        self._seen.setdefault(path, set()).add(key)
        self._tables.setdefault(path, {})

    def register(self, path: tuple[str, ...], data: dict) -> None:
        self._tables[path] = data
        self._seen.setdefault(path, set())

    def finish(self) -> None:
        """Report unknown keys of every table read, then raise everything collected."""
        for path, data in self._tables.items():
            seen = self._seen.get(path, set())
            allowed = self._allowed.get(path, set()) | seen
            for key in data:
                if key not in allowed:
                    hint = difflib.get_close_matches(key, sorted(allowed), n=1, cutoff=0.6)
                    expected = "a known key" + (f' (did you mean "{hint[0]}"?)' if hint
                                                else f" (one of: {', '.join(sorted(allowed))})" if allowed else "")
                    expected = link_name_hint(key, allowed) or expected
                    expected = top_level_hint(path, key, self._tables.get((), {}).keys() | self._seen.get((), set())) or expected
                    self.error(path + (key,), expected, raw_got=f'unknown key "{key}"')
        if self.errors:
            self.errors.sort(key=lambda e: (e.line or 0))
            raise InputErrors(self.errors)

    @property
    def _allowed(self) -> dict[tuple[str, ...], set[str]]:
        return getattr(self, "_allowed_keys", {})

    def allow(self, path: tuple[str, ...], keys) -> None:
        """Declare keys a table may hold without having been read (optional, skipped)."""
        if not hasattr(self, "_allowed_keys"):
            self._allowed_keys = {}
        self._allowed_keys.setdefault(path, set()).update(keys)


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

    def table(self, key: str, required: bool = False) -> "Table | None":
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

    def check_number(self, key, value, rule: "NumberRule", index: int | None = None):
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
