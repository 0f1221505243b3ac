"""The error hierarchy: every failure linkcli expects is one of these.

    LinkcliError                 base: the CLI catches this and nothing else
    ├── InputError               bad input: exit code 2
    │   ├── TomlSyntaxError      the file is not valid TOML
    │   ├── SchemaError          a key is missing, unknown, of the wrong type or value
    │   ├── SolveInputError      input that only solving or analysing shows impossible
    │   └── InputErrors          several of the above, collected from one file
    └── PlotError                a --plot request that cannot be met (exit 2 by default)

Every error has `exit_code` and `lines()` (its stderr lines). Input errors carry their
fields (`path`, `line`, `key`, `expected`, `got`) and format them only in `__str__`, as
`FILE:LINE: key.path: expected ..., found ...`. The key, expected and found parts are
bounded where an error is made (`bounded`, the one rule for every error
line): a word echoed from the file longer than 80 characters keeps its first 60 and its
length, so a line stays a few hundred characters long. Every error pickles with its fields
(`__reduce__`), so it can cross a process boundary. Infeasibility is not an error: it is
a status of the Solution.
"""

from __future__ import annotations

import re

ECHO_LIMIT = 60  # characters kept of one echoed key or value cut in an error line
WORD_LIMIT = 80  # an echoed word (a run without spaces, or a quoted "...") longer than this is cut
KEY_LIMIT = 120  # characters of an error line's key path
PART_LIMIT = 300  # characters of an error line's expected or found part

_LONG = re.compile(r'"([^"]{%d,})"|[^\s"]{%d,}' % (WORD_LIMIT + 1, WORD_LIMIT + 1))


def _cut_word(m: re.Match) -> str:
    """A long word's first ECHO_LIMIT characters, "...", and its length (a quoted word: its
    content, inside its quotes): at most WORD_LIMIT long, so never cut again."""
    inner = m.group(1)
    if inner is not None:
        return f'"{inner[:ECHO_LIMIT]}..." ({len(inner)} characters)'
    word = m.group()
    return f"{word[:ECHO_LIMIT]}... ({len(word)} characters)"


def bounded(text: str, limit: int = PART_LIMIT) -> str:
    """`text` (already one line) with every word longer than WORD_LIMIT cut to its first
    ECHO_LIMIT characters, "..." and its length, then, if still longer than `limit`, cut to exactly
    `limit` characters the same way. Idempotent (bounded(bounded(t)) == bounded(t)): an
    error rebuilt from its fields (unpickled, or collected into InputErrors) keeps its text."""
    if len(text) <= WORD_LIMIT:
        return text
    text = _LONG.sub(_cut_word, text)
    if len(text) > limit:
        tail = f" ... ({len(text)} characters)"
        text = text[:max(0, limit - len(tail))] + tail
    return text


class LinkcliError(Exception):
    """Base of every error linkcli raises on purpose."""

    exit_code = 1

    def lines(self) -> list[str]:
        """The lines printed on stderr for this error."""
        return [str(self)]


class InputError(LinkcliError):
    """Bad input: unreadable file, syntax, schema, impossible data (exit code 2)."""

    exit_code = 2

    def __init__(self, expected: str, got: str | None = None, *, path: str | None = None,
                 line: int | None = None, key: str | None = None) -> None:
        expected = bounded(expected)
        super().__init__(expected)
        self.expected = expected
        self.got = None if got is None else bounded(got)
        self.path = path
        self.line = line
        self.key = bounded(key, KEY_LIMIT) if key else key

    def __reduce__(self):
        return (_rebuild, (type(self), (self.expected, self.got),
                           {"path": self.path, "line": self.line, "key": self.key}))

    def __str__(self) -> str:
        where = self.path or "<input>"
        if self.line is not None:
            where += f":{self.line}"
        text = f"{where}: "
        if self.key:
            text += f"{self.key}: "
        text += f"expected {self.expected}"
        if self.got is not None:
            text += f", found {self.got}"
        return text


def _rebuild(cls, args: tuple, kwargs: dict):
    """Unpickle an error from its fields."""
    return cls(*args, **kwargs)


class TomlSyntaxError(InputError):
    """The file is not valid TOML."""


class SchemaError(InputError):
    """A key is missing, unknown, of the wrong type, or has an impossible value."""


class SolveInputError(InputError):
    """Input that passes every check of the schema but that solving or analysing shows
    impossible (a law not finite at any design within the bounds, two precision positions
    that coincide once wrapped, a tolerance longer than its link): exit 2, with the line
    of the key that causes it."""


MAX_LISTED = 100  # error lines listed for one file; one more line counts the rest


class InputErrors(InputError):
    """Every error found in one file, reported together (one line each): the first
    MAX_LISTED of them (in the order given), then one line counting the `unlisted` rest,
    so that a file of 400,000 unknown keys is 101 lines, not 400,000."""

    def __init__(self, errors: list[InputError], unlisted: int = 0) -> None:
        super().__init__(errors[0].expected, errors[0].got, path=errors[0].path,
                         line=errors[0].line, key=errors[0].key)
        self.errors = errors[:MAX_LISTED]
        self.unlisted = unlisted + len(errors) - len(self.errors)

    def __reduce__(self):
        return (InputErrors, (self.errors, self.unlisted))

    def lines(self) -> list[str]:
        lines = [str(e) for e in self.errors]
        if self.unlisted:
            lines.append(f"{self.path or '<input>'}: expected at most {MAX_LISTED} errors listed per "
                         f"file, found {self.unlisted} more (fix these and run again)")
        return lines

    def __str__(self) -> str:
        return "\n".join(self.lines())


class PlotError(LinkcliError):
    """A plot request that cannot be met (a bad PATH, no matplotlib, an unwritable file):
    one stderr line and an exit code (2: bad input)."""

    def __init__(self, line: str, exit_code: int = 2) -> None:
        super().__init__(line)
        self.exit_code = exit_code

    def __reduce__(self):
        return (PlotError, (str(self), self.exit_code))


def located(exc: LinkcliError, path: str) -> LinkcliError:
    """`exc` with `path` as the file of every error that names none (an error raised deep in
    a solve knows its key, not its file): never `<input>` for a file the CLI read."""
    for error in (exc, *getattr(exc, "errors", ())):
        if getattr(error, "path", "") is None:
            error.path = path
    return exc
