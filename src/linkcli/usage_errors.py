"""Command-line parsing errors as one line, in the form of every other linkcli error:

    linkcli synth: --precision: expected a whole number from 1 to 17, found "x"

click prints a usage error as four lines (usage, a "Try --help" hint, a blank line, the
error); linkcli's lines are `WHERE: KEY: expected ..., found ...` everywhere else, and a script
reading stderr line by line gets one line per problem. `--help` itself, and a command given
no argument at all (`linkcli` alone: the help, exit 2), still print click's usage text.

`OneLineErrors` is the command group's class: it runs click in non-standalone mode, so that
click raises its UsageError here instead of printing it, and exits with click's exit codes
(2 for usage, the command's own otherwise). typer vendors click from 0.28 (typer._click);
`_click()` finds whichever module typer's commands use.
"""

from __future__ import annotations

import difflib
import importlib
import sys

import typer


def _click():
    """The click that typer's commands are made of: typer's vendored copy, or click."""
    return getattr(typer.core, "_click", None) or importlib.import_module("click")


def _abort() -> type:
    """click's Abort (typer has its own beside its vendored click)."""
    return getattr(typer.core, "Abort", None) or _click().exceptions.Abort


def expected_of(param) -> str:
    """What a parameter takes, in words, from its click type (read by its attributes: typer's
    choices are its own class, click's ranges click's)."""
    types = _click().types
    kind = param.type
    choices = getattr(kind, "choices", None)
    if choices:
        return "one of: " + ", ".join(str(getattr(c, "value", c)) for c in choices)
    if isinstance(kind, types.IntParamType):
        low, high = getattr(kind, "min", None), getattr(kind, "max", None)
        if low is not None and high is not None:
            return f"a whole number from {low} to {high}"
        if low is not None or high is not None:
            return f"a whole number >= {low}" if low is not None else f"a whole number <= {high}"
        return "a whole number"
    if isinstance(kind, types.FloatParamType):
        return "a number"
    if param.param_type_name == "argument":
        if param.nargs == -1:
            return "one or more problem files"
        words = (getattr(param, "help", None) or "").rstrip(".")
        return words[:1].lower() + words[1:] if words else f"a {param.human_readable_name}"
    return "a value"


def given_value(param, args: list[str]) -> str | None:
    """The text given to an option on the command line (its last occurrence), or None."""
    found = None
    for k, arg in enumerate(args):
        for opt in getattr(param, "opts", ()):
            if arg == opt and k + 1 < len(args):
                found = args[k + 1]
            elif opt.startswith("--") and arg.startswith(opt + "="):
                found = arg[len(opt) + 1:]
            elif not opt.startswith("--") and arg.startswith(opt) and len(arg) > len(opt):
                found = arg[len(opt):]
    return found


def one_line(exc, args: list[str], root=None) -> str:
    """The one line of a click UsageError (module docstring); `root` the command group (for
    an error raised without a context)."""
    from linkcli.io.terminal_text import shown
    click = _click()
    ctx = exc.ctx
    where = ctx.command_path if ctx is not None else "linkcli"
    command = ctx.command if ctx is not None else root
    sub = getattr(command, "commands", {}).get(args[0]) if args and command is not None else None
    if sub is not None:  # the parser's error about a command's option, raised in the group's context
        command, where = sub, f"{where} {args[0]}"
    if isinstance(exc, click.exceptions.NoSuchOption):
        near = list(exc.possibilities or ()) or difflib.get_close_matches(exc.option_name, _options(command), n=1)
        hint = f" (did you mean {' or '.join(near[:2])}?)" if near else ""
        return (f"{where}: {exc.option_name}: expected an option of {where}{hint}; {where} --help lists them, "
                f"found {shown(exc.option_name, 60)}")
    if isinstance(exc, click.exceptions.BadOptionUsage) and "requires an argument" in exc.format_message():
        param = _param(command, exc.option_name)
        what = expected_of(param) if param is not None else "a value"
        return f"{where}: {exc.option_name}: expected {what} after it, found nothing"
    if isinstance(exc, click.exceptions.BadParameter) and exc.param is not None:
        param = exc.param
        name = param.opts[0] if param.param_type_name == "option" and param.opts else param.human_readable_name
        if isinstance(exc, click.exceptions.MissingParameter):
            return f"{where}: {name}: expected {expected_of(param)}, found nothing"
        value = given_value(param, args)
        found = f'"{shown(value, 60)}"' if value is not None else shown(exc.format_message(), 120)
        return f"{where}: {name}: expected {expected_of(param)}, found {found}"
    message = exc.format_message()
    if "does not take a value" in message and isinstance(exc, click.exceptions.BadOptionUsage):
        given = next((a.split("=", 1)[1] for a in args if a.startswith(exc.option_name + "=")), "")
        return f'{where}: {exc.option_name}: expected no value (a flag), found "{shown(given, 60)}"'
    if message.startswith("No such command"):
        commands = list(getattr(ctx.command, "commands", {})) if ctx is not None else []
        word = message.split("'")[1] if "'" in message else ""
        near = difflib.get_close_matches(word.lower(), commands, n=1)
        hint = f' (did you mean "{near[0]}"?)' if near else ""
        return f'{where}: COMMAND: expected one of: {", ".join(commands)}{hint}, found "{shown(word, 60)}"'
    if message.startswith("Got unexpected extra argument"):
        extra = message[message.rfind("(") + 1:message.rfind(")")] if "(" in message else message
        usage = " ".join(ctx.command.collect_usage_pieces(ctx)) if ctx is not None else ""
        return f"{where}: expected the arguments {usage}, found more: {shown(extra, 120)}"
    return f"{where}: expected a command line that {where} --help describes, found: {shown(message, 200)}"


def _options(command) -> list[str]:
    if command is None:
        return []
    return [opt for p in command.params for opt in getattr(p, "opts", ())]


def _param(command, option: str):
    if command is None:
        return None
    return next((p for p in command.params if option in getattr(p, "opts", ())), None)


class OneLineErrors(typer.core.TyperGroup):
    """The command group: click's usage errors as one line each (module docstring)."""

    def main(self, args=None, prog_name=None, **extra):
        click = _click()
        args = list(sys.argv[1:] if args is None else args)
        extra["standalone_mode"] = False
        try:
            code = super().main(args=args, prog_name=prog_name, **extra)
        except click.exceptions.UsageError as exc:
            if type(exc).__name__ == "NoArgsIsHelpError":
                exc.show()  # `linkcli` alone: the help text, as click prints it
                sys.exit(exc.exit_code)
            from linkcli.io.terminal_text import write_error
            try:
                line = one_line(exc, args, self)
            except Exception:  # a click or typer this module does not know: click's own words, one line
                line = f"linkcli: expected a command line that linkcli --help describes, found: {exc.format_message()}"
            write_error(line)
            sys.exit(2)
        except click.exceptions.ClickException as exc:
            exc.show()
            sys.exit(exc.exit_code)
        except _abort():
            from linkcli.io.terminal_text import write_error
            write_error("interrupted")
            sys.exit(130)
        sys.exit(code if isinstance(code, int) else 0)
