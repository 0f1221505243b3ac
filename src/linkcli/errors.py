"""The error hierarchy: every failure linkcli expects is one of these.

    LinkcliError                 base: the CLI catches this and nothing else
    ├── InputError               bad input: exit code 2
    │   ├── TomlSyntaxError      the file is not valid TOML
    │   ├── SchemaError          a key is missing, unknown, of the wrong type or value
    │   └── InputErrors          several of the above, collected from one file
    └── SolveError               the solver itself failed (not infeasibility: that is a status)

Errors carry their fields (`path`, `line`, `key`, `expected`, `got`) and format them only
in `__str__`, as `FILE:LINE: key.path: expected ..., found ...`.
"""

from __future__ import annotations


class LinkcliError(Exception):
    """Base of every error linkcli raises on purpose."""

    exit_code = 1


class InputError(LinkcliError):
    """Bad input: unreadable file, syntax, schema, impossible data (exit code 2)."""

    exit_code = 2

    def __init__(self, expected: str, got: str | None = None, *, path: str | None = None,
                 line: int | None = None, key: str | None = None) -> None:
        super().__init__(expected)
        self.expected = expected
        self.got = got
        self.path = path
        self.line = line
        self.key = key

    def lines(self) -> list[str]:
        return [str(self)]

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


class TomlSyntaxError(InputError):
    """The file is not valid TOML."""


class SchemaError(InputError):
    """A key is missing, unknown, of the wrong type, or has an impossible value."""


class InputErrors(InputError):
    """Every error found in one file, reported together (one line each)."""

    def __init__(self, errors: list[InputError]) -> None:
        super().__init__(errors[0].expected, errors[0].got, path=errors[0].path,
                         line=errors[0].line, key=errors[0].key)
        self.errors = errors

    def lines(self) -> list[str]:
        return [str(e) for e in self.errors]

    def __str__(self) -> str:
        return "\n".join(self.lines())


class SolveError(LinkcliError):
    """A solver could not run to completion (a bug or an impossible request)."""

    exit_code = 1
