"""Safe evaluation of path expressions such as ``"10*sin(2*pi*t)"``.

An expression is parsed with :mod:`ast` and its tree is walked against an
allow-list; nothing is ever passed to ``eval`` or ``exec``.  Allowed:

* numbers (integers and decimals, evaluated as floats), the variable ``t``
  (or the names given in ``variables``), the constants ``pi`` and ``e``;
* ``+ - * / **``, unary ``+``/``-``, parentheses;
* the functions ``sin cos tan asin acos atan atan2 sqrt exp log abs min max``
  (``atan2(y, x)``; ``min``/``max`` of two or more arguments, element-wise).

Everything else (attribute access, subscripts, calls of other names, lambdas,
comparisons, strings, keyword arguments ...) raises :class:`InputError`
naming the offending token and its 1-based column.  Evaluation is vectorised
over a numpy array ``t``.

Examples
--------
>>> import numpy as np
>>> from screwkit.pm import evaluate
>>> evaluate("70 + 30*t", np.array([0.0, 0.5, 1.0]))
array([ 70.,  85., 100.])
>>> evaluate("t.__class__", np.zeros(2))  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
screwkit.errors.InputError: expression 't.__class__': attribute access ... (column 2)
"""

from __future__ import annotations

import ast
import re
from dataclasses import dataclass

import numpy as np

from ..legs._guards import MAX_NUMBER_CHARS, shorten
from ..errors import InputError

__all__ = ["Expression", "parse_expression", "evaluate", "FUNCTIONS", "CONSTANTS",
           "MAX_LENGTH"]

#: Allowed functions: name -> (numpy function, minimum arity, maximum arity or None).
FUNCTIONS = {
    "sin": (np.sin, 1, 1), "cos": (np.cos, 1, 1), "tan": (np.tan, 1, 1),
    "asin": (np.arcsin, 1, 1), "acos": (np.arccos, 1, 1), "atan": (np.arctan, 1, 1),
    "atan2": (np.arctan2, 2, 2), "sqrt": (np.sqrt, 1, 1), "exp": (np.exp, 1, 1),
    "log": (np.log, 1, 1), "abs": (np.abs, 1, 1),
    "min": (np.minimum, 2, None), "max": (np.maximum, 2, None),
}

#: Named constants.
CONSTANTS = {"pi": float(np.pi), "e": float(np.e)}

#: Longest accepted expression (characters): guards the parser's recursion.
MAX_LENGTH = 2000

_DECIMAL = re.compile(r"(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][-+]?[0-9]+)?")

_BINOPS = {ast.Add: np.add, ast.Sub: np.subtract, ast.Mult: np.multiply,
           ast.Div: np.true_divide, ast.Pow: np.power}
_BINOP_SYMBOLS = {ast.Mod: "%", ast.FloorDiv: "//", ast.MatMult: "@", ast.LShift: "<<",
                  ast.RShift: ">>", ast.BitOr: "|", ast.BitXor: "^", ast.BitAnd: "&"}
_UNARY = {ast.UAdd: np.positive, ast.USub: np.negative}

_NODE_WORDS = {
    ast.Attribute: "attribute access", ast.Subscript: "subscript", ast.Lambda: "lambda",
    ast.Compare: "comparison", ast.BoolOp: "boolean operator", ast.IfExp: "conditional",
    ast.List: "list", ast.Tuple: "tuple", ast.Set: "set", ast.Dict: "dict",
    ast.ListComp: "comprehension", ast.SetComp: "comprehension",
    ast.DictComp: "comprehension", ast.GeneratorExp: "generator",
    ast.Starred: "starred argument", ast.NamedExpr: "assignment ':='",
    ast.JoinedStr: "string", ast.Await: "await", ast.Yield: "yield",
    ast.YieldFrom: "yield", ast.Slice: "slice",
}


def _fail(text: str, what: str, node=None, column: int | None = None) -> InputError:
    if node is not None and getattr(node, "col_offset", None) is not None:
        column = node.col_offset + 1
    where = f" (column {column})" if column is not None else ""
    return InputError(f"expression {shorten(text, 80)}: {what}{where}")


def _token(text: str, node) -> str:
    """The source text of ``node`` (shortened), for messages."""
    seg = ast.get_source_segment(text, node) or type(node).__name__
    return seg if len(seg) <= 30 else seg[:27] + "..."


class _Checker:
    """Walks a parsed tree and rejects everything outside the allow-list."""

    def __init__(self, text: str, variables: frozenset):
        self.text = text
        self.variables = variables

    def check(self, node):
        text = self.text
        if isinstance(node, ast.Expression):
            return self.check(node.body)
        if isinstance(node, ast.Constant):
            v = node.value
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise _fail(text, f"literal {_token(text, node)} is not a number", node)
            lit = ast.get_source_segment(text, node) or ""
            if len(lit) > MAX_NUMBER_CHARS:
                raise _fail(text, f"a number of {len(lit)} characters is too long (at most "
                                  f"{MAX_NUMBER_CHARS})", node)
            if not _DECIMAL.fullmatch(lit):
                raise _fail(text, f"number {_token(text, node)} is not written in decimal "
                                  "digits (e.g. 12.5 or 1e-3)", node)
            try:
                x = float(v)
            except OverflowError:
                x = float("inf")
            if not np.isfinite(x):
                raise _fail(text, f"number {_token(text, node)} overflows", node)
            return
        if isinstance(node, ast.Name):
            if node.id in self.variables or node.id in CONSTANTS:
                return
            if node.id in FUNCTIONS:
                raise _fail(text, f"function {node.id!r} used without arguments", node)
            allowed = ", ".join(sorted(self.variables) + sorted(CONSTANTS))
            raise _fail(text, f"unknown name {node.id!r} (allowed names: {allowed})", node)
        if isinstance(node, ast.BinOp):
            if type(node.op) not in _BINOPS:
                sym = _BINOP_SYMBOLS.get(type(node.op), type(node.op).__name__)
                # locate the operator: first occurrence after the left operand
                col = None
                if getattr(node.left, "end_col_offset", None) is not None:
                    idx = text.find(sym, node.left.end_col_offset)
                    col = idx + 1 if idx >= 0 else None
                raise _fail(text, f"operator {sym!r} is not allowed (use + - * / **)",
                            column=col if col is not None else node.col_offset + 1)
            self.check(node.left)
            self.check(node.right)
            return
        if isinstance(node, ast.UnaryOp):
            if type(node.op) not in _UNARY:
                sym = {ast.Not: "not", ast.Invert: "~"}.get(type(node.op), "?")
                raise _fail(text, f"operator {sym!r} is not allowed", node)
            self.check(node.operand)
            return
        if isinstance(node, ast.Call):
            f = node.func
            if isinstance(f, ast.Attribute):
                self.check(f)  # reports the attribute access itself
            if not isinstance(f, ast.Name):
                raise _fail(text, f"call of {_token(text, f)!r} is not allowed "
                                  f"(functions: {', '.join(FUNCTIONS)})", f)
            if f.id not in FUNCTIONS:
                raise _fail(text, f"unknown function {f.id!r} (functions: "
                                  f"{', '.join(FUNCTIONS)})", f)
            if node.keywords:
                kw = node.keywords[0]
                raise _fail(text, f"keyword argument {_token(text, kw)!r} is not allowed",
                            kw if hasattr(kw, "col_offset") else node)
            _, lo, hi = FUNCTIONS[f.id]
            n = len(node.args)
            if n < lo or (hi is not None and n > hi):
                want = str(lo) if hi == lo else (f"{lo} or more" if hi is None else f"{lo}-{hi}")
                raise _fail(text, f"function {f.id!r} takes {want} argument"
                                  f"{'s' * (want != '1')}, got {n}", f)
            for a in node.args:
                self.check(a)
            return
        word = _NODE_WORDS.get(type(node), type(node).__name__)
        tok = _token(text, node)
        if isinstance(node, ast.Attribute):
            tok = "." + node.attr
            col = None
            if getattr(node.value, "end_col_offset", None) is not None:
                idx = text.find(".", node.value.end_col_offset)
                col = idx + 1 if idx >= 0 else None
            raise _fail(text, f"{word} {tok!r} is not allowed",
                        column=col or node.col_offset + 1)
        raise _fail(text, f"{word} {tok!r} is not allowed", node)


class _Evaluator:
    def __init__(self, env: dict):
        self.env = env

    def run(self, node):
        if isinstance(node, ast.Expression):
            return self.run(node.body)
        if isinstance(node, ast.Constant):
            return np.float64(node.value)
        if isinstance(node, ast.Name):
            return self.env[node.id] if node.id in self.env else np.float64(CONSTANTS[node.id])
        if isinstance(node, ast.BinOp):
            return _BINOPS[type(node.op)](self.run(node.left), self.run(node.right))
        if isinstance(node, ast.UnaryOp):
            return _UNARY[type(node.op)](self.run(node.operand))
        if isinstance(node, ast.Call):
            fn = FUNCTIONS[node.func.id][0]
            args = [self.run(a) for a in node.args]
            if fn in (np.minimum, np.maximum):
                out = args[0]
                for a in args[1:]:
                    out = fn(out, a)
                return out
            return fn(*args)
        raise AssertionError(f"unchecked node {type(node).__name__}")  # pragma: no cover


@dataclass(frozen=True)
class Expression:
    """A checked expression, ready to evaluate.

    Attributes
    ----------
    text : str
        The source text.
    variables : tuple of str
        Names of the free variables (default ``("t",)``).
    """

    text: str
    variables: tuple
    tree: ast.Expression

    def __call__(self, t=None, *, check_finite: bool = True, **values) -> np.ndarray:
        """Evaluate.

        Parameters
        ----------
        t : array_like, shape (N,) or scalar
            Value of ``t`` (when ``"t"`` is a variable).
        check_finite : bool
            Raise :class:`InputError` on a NaN or infinite result (``log(0)``,
            ``sqrt(-1)``, overflow), naming the first offending sample.
        **values
            Values of other variables.

        Returns
        -------
        ndarray
            Shape of the broadcast inputs (a constant expression is broadcast
            to the shape of ``t``).
        """
        if t is not None:
            values = {"t": t, **values}
        missing = [v for v in self.variables if v not in values]
        if missing:
            raise InputError(f"expression {self.text!r}: no value given for {', '.join(missing)}")
        env = {}
        for k, v in values.items():
            arr = np.asarray(v, dtype=float)
            env[k] = arr
        shape = np.broadcast_shapes(*(a.shape for a in env.values())) if env else ()
        with np.errstate(all="ignore"):
            out = np.broadcast_to(np.asarray(_Evaluator(env).run(self.tree), dtype=float),
                                  shape).copy()
        if check_finite and not np.all(np.isfinite(out)):
            idx = np.argwhere(~np.isfinite(out))[0]
            at = ", ".join(f"{k} = {np.broadcast_to(a, shape)[tuple(idx)]:.6g}"
                           for k, a in env.items())
            what = "NaN" if np.isnan(out[tuple(idx)]) else "infinite"
            raise InputError(f"expression {self.text!r} is {what} at {at} "
                             f"(sample {int(np.ravel_multi_index(idx, shape)) if shape else 0})")
        return out


def parse_expression(text: str, variables=("t",)) -> Expression:
    """Parse and check an expression (see the module docstring for the allowed syntax).

    Parameters
    ----------
    text : str
    variables : sequence of str
        Names that may appear as free variables.

    Returns
    -------
    Expression

    Raises
    ------
    InputError
        On a syntax error or anything outside the allow-list, naming the token
        and its 1-based column.
    """
    if not isinstance(text, str):
        raise InputError(f"expression must be a string, got {type(text).__name__}")
    if len(text) > MAX_LENGTH:
        raise InputError(f"expression of {len(text)} characters is too long (max {MAX_LENGTH})")
    if not text.strip():
        raise InputError("empty expression")
    if "\n" in text or "\r" in text:
        raise InputError(f"expression {text!r}: line breaks are not allowed")
    src = text.strip()
    lead = len(text) - len(text.lstrip())
    try:
        tree = ast.parse(src, mode="eval")
    except SyntaxError as exc:
        col = exc.offset + lead if exc.offset else len(text.rstrip()) + 1
        m = re.match(r"\w+|\S", text[col - 1:]) if 0 < col <= len(text) else None
        near_txt = f" near {m.group(0)!r}" if m else " at the end (incomplete expression)"
        raise InputError(f"expression {text!r}: syntax error ({exc.msg}){near_txt} "
                         f"(column {col})") from None
    except (RecursionError, MemoryError, ValueError) as exc:
        raise InputError(f"expression {text!r} cannot be parsed ({type(exc).__name__})") from None
    vars_ = frozenset(variables)
    for v in vars_:
        if v in CONSTANTS or v in FUNCTIONS:
            raise InputError(f"variable name {v!r} clashes with a constant or function")
    try:
        _Checker(src, vars_).check(tree)
    except InputError as exc:
        if lead:  # re-report with columns of the original text
            msg = str(exc).replace(repr(src), repr(text), 1)

            msg = re.sub(r"\(column (\d+)\)$", lambda m: f"(column {int(m.group(1)) + lead})", msg)
            raise InputError(msg) from None
        raise
    except RecursionError:
        raise InputError(f"expression {text!r} is nested too deeply") from None
    return Expression(text, tuple(variables), tree)


def evaluate(text: str, t, *, check_finite: bool = True) -> np.ndarray:
    """Evaluate an expression in ``t``, vectorised.

    Parameters
    ----------
    text : str
        E.g. ``"10*sin(2*pi*t)"``.
    t : array_like, shape (N,)
    check_finite : bool
        Raise on NaN/inf results (default).

    Returns
    -------
    ndarray, shape (N,)
    """
    return parse_expression(text)(t, check_finite=check_finite)
