"""Target expressions: text -> a numpy function, through an `ast` whitelist (never eval).

docs/format.md allows in a target law: numbers, `+ - * / **`, unary `+ -`, parentheses,
the constants `pi` and `e`, the variables of the form (`phi, phi0, psi0` or `x`), and
calls of one argument to `sin cos tan asin acos atan sqrt exp log log10 abs`. Anything
else (attribute access, calls of other names, subscripts, lambdas, comprehensions,
comparisons, strings, keywords) is an input error naming the offending token.

The text is parsed with `ast.parse(..., mode="eval")` only to read its syntax tree; it is
never compiled or executed. The tree is checked node by node and turned into plain
nested tuples:

    ("const", value) | ("var", name) | ("neg", node) | ("bin", op, left, right)
    | ("call", function, node)

which `Expression.__call__` walks with numpy ufuncs (vectorized, any broadcast shape) and
`Expression.scalar` with the math module (no numpy: `linkcli check` stays light).
Constant subexpressions are folded when compiled: a non-finite constant (`log(-1)`,
`1/0`, `10**400`) is rejected there, and so is a constant exponent larger than
MAX_EXPONENT in magnitude (`9**9**9`). Text is limited to MAX_LENGTH characters.
Evaluation never raises: a domain error gives NaN and an overflow inf, which callers
test with `isfinite`.
"""

from __future__ import annotations

import ast
import difflib
import math
import operator
from dataclasses import dataclass
from typing import NoReturn

from linkcli.errors import InputError

FUNCTIONS = ("sin", "cos", "tan", "asin", "acos", "atan", "sqrt", "exp", "log", "log10", "abs")
CONSTANTS = {"pi": math.pi, "e": math.e}
MAX_LENGTH = 500  # characters of expression text
MAX_EXPONENT = 100  # |constant exponent| allowed in a ** b
MAX_DEPTH = 250  # operations nested in one another: a flat sum of MAX_LENGTH characters ("x+1+1+...", two
# characters an operation) nests 249 deep and is taken; deeper takes stacked signs ("----x"); the
# evaluation recurses this deep (Python's parser refuses parentheses nested past 200 itself)
_BINOPS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.Pow: "**"}
_DESCRIBE = {  # node types refused, as the user would name them
    ast.Attribute: "attribute access", ast.Subscript: "a subscript", ast.Lambda: "a lambda",
    ast.ListComp: "a comprehension", ast.SetComp: "a comprehension",
    ast.DictComp: "a comprehension", ast.GeneratorExp: "a comprehension",
    ast.Compare: "a comparison", ast.BoolOp: "a boolean operator", ast.IfExp: "a conditional",
    ast.List: "a list", ast.Tuple: "a tuple", ast.Dict: "a dict", ast.Set: "a set",
    ast.JoinedStr: "a string", ast.NamedExpr: "an assignment", ast.Starred: "a starred argument",
    ast.Await: "await", ast.Yield: "yield", ast.YieldFrom: "yield", ast.Slice: "a slice",
}


class ExpressionError(InputError):
    """An expression outside the whitelist; `got` names the offending token."""


def describe_grammar(variables: tuple[str, ...]) -> str:
    """The `expected` text of every expression error."""
    names = ", ".join(variables)
    return (f"an expression in {names} of numbers, + - * / **, parentheses, pi, e and "
            f"{' '.join(FUNCTIONS)}")


@dataclass(frozen=True)
class Expression:
    """A checked expression: its text, the variables it may use, and its tuple tree."""

    text: str
    variables: tuple[str, ...]
    tree: tuple

    def __call__(self, **values):
        """Evaluate with numpy on arrays that broadcast together; NaN or inf, never an error."""
        import numpy as np
        env = {k: np.asarray(v, dtype=float) for k, v in values.items()}
        missing = [v for v in self.variables if v not in env and _uses(self.tree, v)]
        if missing:
            raise KeyError(f"no value for {', '.join(missing)}")
        with np.errstate(all="ignore"):
            out = _walk(self.tree, env, _numpy_ops(), _numpy_functions())
            return np.asarray(out, dtype=float) + np.zeros(np.broadcast_shapes(*(e.shape for e in env.values())))

    def scalar(self, **values) -> float:
        """Evaluate with the math module on floats; NaN or inf, never an error."""
        env = {k: float(v) for k, v in values.items()}
        return float(_walk(self.tree, env, _MATH_OPS, _MATH_FUNCTIONS))

    def uses(self, name: str) -> bool:
        return _uses(self.tree, name)


def compile_expression(text: str, variables: tuple[str, ...]) -> Expression:
    """Check `text` against the whitelist and build its tree; ExpressionError if refused."""
    expected = describe_grammar(variables)
    if len(text) > MAX_LENGTH:
        raise ExpressionError(f"an expression of at most {MAX_LENGTH} characters",
                              f"{len(text)} characters")
    if not text.strip():
        raise ExpressionError(expected, "an empty expression")
    flat = text.replace("\r", " ").replace("\n", " ").replace("\t", " ")  # TOML multi-line strings
    try:
        node = ast.parse(flat.strip(), mode="eval")
    except SyntaxError as exc:
        col = f" at column {exc.offset}" if exc.offset else ""
        why = f" ({exc.msg})" if exc.msg else ""
        raise ExpressionError(expected, f'a syntax error{why}{col} in "{_short(text)}"') from None
    except (RecursionError, MemoryError, ValueError):
        raise ExpressionError(expected, f'an expression too deeply nested: "{_short(text)}"') from None
    tree = _Builder(flat.strip(), tuple(variables), expected).build(node.body)
    if _depth(tree) > MAX_DEPTH:
        raise ExpressionError(expected, f"an expression nested more than {MAX_DEPTH} operations deep: "
                                        f'"{_short(text)}"')
    return Expression(text=text, variables=tuple(variables), tree=tree)


def _depth(tree: tuple) -> int:
    """Nesting depth of a tree, without recursion."""
    deepest, stack = 0, [(tree, 1)]
    while stack:
        node, d = stack.pop()
        deepest = max(deepest, d)
        stack.extend((t, d + 1) for t in node[1:] if isinstance(t, tuple))
    return deepest


class _Builder:
    """Whitelist check and tuple tree of one parsed expression, folding constants."""

    def __init__(self, text: str, variables: tuple[str, ...], expected: str) -> None:
        self.text = text
        self.variables = variables
        self.expected = expected

    def fail(self, got: str) -> NoReturn:
        raise ExpressionError(self.expected, got)

    def segment(self, node) -> str:
        return _short(ast.get_source_segment(self.text, node) or type(node).__name__)

    def build(self, node) -> tuple:
        try:
            return self._build(node)
        except RecursionError:
            self.fail(f'an expression too deeply nested: "{_short(self.text)}"')

    def _build(self, node) -> tuple:
        if isinstance(node, ast.Constant):
            v = node.value
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                if isinstance(v, str):
                    self.fail(f'a string "{self.segment(node)}"')
                self.fail(f"the complex number {v!r}" if isinstance(v, complex) else f"the constant {v!r}")
            try:
                value = float(v)
            except OverflowError:
                self.fail(f'a number too large: "{self.segment(node)}"')
            return self.constant(value, node)
        if isinstance(node, ast.Name):
            if node.id in self.variables:
                return ("var", node.id)
            if node.id in CONSTANTS:
                return ("const", CONSTANTS[node.id])
            if node.id in FUNCTIONS:
                self.fail(f'"{node.id}" without an argument (write {node.id}(...))')
            hint = difflib.get_close_matches(node.id, list(self.variables) + list(CONSTANTS) + list(FUNCTIONS),
                                             n=1, cutoff=0.6)
            extra = f' (did you mean "{hint[0]}"?)' if hint else ""
            self.fail(f'the unknown name "{_short(node.id)}"{extra}')
        if isinstance(node, ast.UnaryOp):
            if isinstance(node.op, ast.UAdd):
                return self._build(node.operand)
            if isinstance(node.op, ast.USub):
                inner = self._build(node.operand)
                return self.fold(("neg", inner), node)
            op = {ast.Not: "not", ast.Invert: "~"}.get(type(node.op), type(node.op).__name__)
            self.fail(f'the operator "{op}" in "{self.segment(node)}"')
        if isinstance(node, ast.BinOp):
            op = _BINOPS.get(type(node.op))
            if op is None:
                self.fail(f'an operator not allowed in "{self.segment(node)}"')
            left = self._build(node.left)
            right = self._build(node.right)
            if op == "**" and right[0] == "const" and abs(right[1]) > MAX_EXPONENT:
                self.fail(f'the exponent {_num(right[1])} in "{self.segment(node)}" '
                          f"(a constant exponent may be at most {MAX_EXPONENT} in magnitude)")
            return self.fold(("bin", op, left, right), node)
        if isinstance(node, ast.Call):
            return self.call(node)
        kind = _DESCRIBE.get(type(node), f"a {type(node).__name__} expression")
        if isinstance(node, ast.Attribute):
            self.fail(f'attribute access ".{node.attr}" in "{self.segment(node)}"')
        if isinstance(node, ast.Lambda):
            self.fail(f'"lambda" (a lambda) in "{self.segment(node)}"')
        self.fail(f'{kind} "{self.segment(node)}"')

    def call(self, node: ast.Call) -> tuple:
        func = node.func
        if not isinstance(func, ast.Name):
            if isinstance(func, ast.Attribute):
                self.fail(f'attribute access ".{func.attr}" in "{self.segment(node)}"')
            self.fail(f'a call of "{self.segment(func)}"')
        name = func.id
        if name not in FUNCTIONS:
            what = "a variable" if name in self.variables or name in CONSTANTS else "not an allowed function"
            self.fail(f'a call of "{_short(name)}" ({what})')
        if node.keywords:
            self.fail(f'a keyword argument in "{self.segment(node)}" ({name} takes one plain argument)')
        if node.args and isinstance(node.args[0], ast.Starred):
            self.fail(f'a starred argument in "{self.segment(node)}"')
        if len(node.args) != 1:
            self.fail(f'{name} with {len(node.args)} arguments in "{self.segment(node)}" ({name} takes one)')
        return self.fold(("call", name, self._build(node.args[0])), node)

    def constant(self, value: float, node) -> tuple:
        if not math.isfinite(value):
            self.fail(f'a value that is not finite: "{self.segment(node)}"')
        return ("const", value)

    def fold(self, tree: tuple, node) -> tuple:
        """A subtree of constants only becomes its (finite) value."""
        if all(part[0] == "const" for part in tree[1:] if isinstance(part, tuple)):
            value = _walk(tree, {}, _MATH_OPS, _MATH_FUNCTIONS)
            if not math.isfinite(value):
                self.fail(f'"{self.segment(node)}" = {_num(value)} (a constant that is not finite)')
            return ("const", value)
        return tree


def _short(text: str, n: int = 40) -> str:
    text = " ".join(str(text).split())
    return text if len(text) <= n else text[: n - 3] + "..."


def _num(x: float) -> str:
    if not math.isfinite(x):
        return "nan" if math.isnan(x) else ("inf" if x > 0 else "-inf")
    return repr(int(x)) if float(x).is_integer() and abs(x) < 1e16 else f"{x:g}"


def _uses(tree: tuple, name: str) -> bool:
    stack = [tree]
    while stack:
        node = stack.pop()
        if node[0] == "var" and node[1] == name:
            return True
        stack.extend(t for t in node[1:] if isinstance(t, tuple))
    return False


def _walk(tree: tuple, env: dict, ops: dict, funcs: dict):
    kind = tree[0]
    if kind == "const":
        return tree[1]
    if kind == "var":
        return env[tree[1]]
    if kind == "neg":
        return -_walk(tree[1], env, ops, funcs)
    if kind == "bin":
        return ops[tree[1]](_walk(tree[2], env, ops, funcs), _walk(tree[3], env, ops, funcs))
    return funcs[tree[1]](_walk(tree[2], env, ops, funcs))


# -- numpy: ufuncs, IEEE results under errstate(all="ignore") -------------------------

def _numpy_ops() -> dict:
    import numpy as np
    return {"+": np.add, "-": np.subtract, "*": np.multiply, "/": np.true_divide, "**": np.power}


def _numpy_functions() -> dict:
    import numpy as np
    return {"sin": np.sin, "cos": np.cos, "tan": np.tan, "asin": np.arcsin, "acos": np.arccos,
            "atan": np.arctan, "sqrt": np.sqrt, "exp": np.exp, "log": np.log, "log10": np.log10,
            "abs": np.abs}


# -- math: scalars, errors turned into NaN or inf -------------------------------------

def _safe(fn):
    def wrapped(*args):
        if any(isinstance(a, float) and math.isnan(a) for a in args):
            return math.nan
        try:
            return float(fn(*args))
        except OverflowError:
            return math.inf
        except (ValueError, ZeroDivisionError):
            return math.nan
    return wrapped


def _div(x: float, y: float) -> float:
    if y == 0.0:
        return math.nan if x == 0.0 else math.copysign(math.inf, x) * math.copysign(1.0, y)
    return x / y


_MATH_OPS = {"+": _safe(operator.add), "-": _safe(operator.sub), "*": _safe(operator.mul),
             "/": _safe(_div), "**": _safe(math.pow)}
_MATH_FUNCTIONS = {"sin": _safe(math.sin), "cos": _safe(math.cos), "tan": _safe(math.tan),
                   "asin": _safe(math.asin), "acos": _safe(math.acos), "atan": _safe(math.atan),
                   "sqrt": _safe(math.sqrt), "exp": _safe(math.exp), "log": _safe(math.log),
                   "log10": _safe(math.log10), "abs": _safe(abs)}
