"""Exact first and second time derivatives of path expressions (Taylor-mode automatic
differentiation of the safe expression tree).

A path expression (:mod:`screwkit.pm._expressions`) is evaluated on *jets*: truncated
Taylor series ``(f, f', f'')`` in ``t``.  Every node of the checked tree has its rule
(sum, product and quotient rules, the chain rule with the first and second derivative of
each allowed function), so the derivatives are exact to rounding, cost a small constant
times the value, and need no step size.  Why not the alternatives: finite differences lose
half the digits for the first derivative and more for the second; the complex step gives
the first derivative only (the second needs multicomplex numbers, which is this method in
disguise); symbolic differentiation of the tree grows the expression and needs a
simplifier.

Non-smooth points: ``abs`` has derivative ``sign(u)`` (0 at 0); ``min`` and ``max`` take
the derivatives of the argument they select (the first one on a tie).

Examples
--------
>>> import numpy as np
>>> from screwkit.pm import parse_expression
>>> f, d1, d2 = derivatives(parse_expression("3*t**2 + sin(t)"), np.array([0.0, 1.0]))
>>> d1.round(6).tolist(), d2.round(6).tolist()
([1.0, 6.540302], [6.0, 5.158529])
"""

from __future__ import annotations

import ast

import numpy as np

from ..errors import InputError
from ..pm import CONSTANTS

__all__ = ["Jet", "derivatives"]


class Jet:
    """A value and its first two derivatives with respect to ``t`` (arrays)."""

    __slots__ = ("f", "d", "dd")

    def __init__(self, f, d, dd):
        self.f, self.d, self.dd = f, d, dd

    @classmethod
    def constant(cls, x, like):
        z = np.zeros_like(like)
        return cls(np.full_like(like, float(x)), z, z)

    def __add__(self, o):
        return Jet(self.f + o.f, self.d + o.d, self.dd + o.dd)

    def __sub__(self, o):
        return Jet(self.f - o.f, self.d - o.d, self.dd - o.dd)

    def __mul__(self, o):
        return Jet(self.f * o.f, self.d * o.f + self.f * o.d,
                   self.dd * o.f + 2.0 * self.d * o.d + self.f * o.dd)

    def __truediv__(self, o):
        q = self.f / o.f
        d = (self.d - q * o.d) / o.f
        return Jet(q, d, (self.dd - 2.0 * d * o.d - q * o.dd) / o.f)

    def __neg__(self):
        return Jet(-self.f, -self.d, -self.dd)

    def chain(self, g, g1, g2):
        """``h(self)`` with ``h = g``, ``h' = g1``, ``h'' = g2`` evaluated at the value."""
        return Jet(g, g1 * self.d, g2 * self.d ** 2 + g1 * self.dd)

    def power(self, o):
        if not (np.any(o.d) or np.any(o.dd)):            # constant exponent: u ** c
            c, x = o.f, self.f
            g1 = np.where(c == 0, 0.0, c * x ** (c - 1.0))
            g2 = np.where((c == 0) | (c == 1), 0.0, c * (c - 1.0) * x ** (c - 2.0))
            return self.chain(x ** c, g1, g2)
        if not (np.any(self.d) or np.any(self.dd)):      # constant base: exp(v ln c)
            c, h = self.f, self.f ** o.f
            # 0 ** v is 0 for every v > 0 near the sample: its rates are 0, not 0 * inf
            zero = (c == 0) & (o.f > 0)
            ln = np.log(np.where(zero, 1.0, c))
            return Jet(h, np.where(zero, 0.0, h * ln * o.d),
                       np.where(zero, 0.0, h * (ln * o.dd + (ln * o.d) ** 2)))
        j = _unary("exp", o * _unary("log", self))       # u ** v = exp(v log u) ...
        j.f = self.f ** o.f                  # (... but its value 0 ** 0 = 1, not exp(nan))
        return j


def _unary(name, u: Jet) -> Jet:
    x = u.f
    if name == "sin":
        s, c = np.sin(x), np.cos(x)
        return u.chain(s, c, -s)
    if name == "cos":
        s, c = np.sin(x), np.cos(x)
        return u.chain(c, -s, -c)
    if name == "tan":
        t = np.tan(x)
        s2 = 1.0 + t * t
        return u.chain(t, s2, 2.0 * t * s2)
    if name in ("asin", "acos"):
        r = 1.0 / np.sqrt(1.0 - x * x)
        sign = 1.0 if name == "asin" else -1.0
        return u.chain(np.arcsin(x) if name == "asin" else np.arccos(x), sign * r,
                       sign * x * r ** 3)
    if name == "atan":
        r = 1.0 / (1.0 + x * x)
        return u.chain(np.arctan(x), r, -2.0 * x * r * r)
    if name == "sqrt":
        s = np.sqrt(x)
        return u.chain(s, 0.5 / s, -0.25 / (s * x))
    if name == "exp":
        e = np.exp(x)
        return u.chain(e, e, e)
    if name == "log":
        return u.chain(np.log(x), 1.0 / x, -1.0 / (x * x))
    if name == "abs":
        s = np.sign(x)
        return u.chain(np.abs(x), s, np.zeros_like(x))
    raise AssertionError(name)  # pragma: no cover


def _atan2(y: Jet, x: Jet) -> Jet:
    r2 = x.f ** 2 + y.f ** 2
    n = x.f * y.d - y.f * x.d
    n1 = x.f * y.dd - y.f * x.dd
    r21 = 2.0 * (x.f * x.d + y.f * y.d)
    return Jet(np.arctan2(y.f, x.f), n / r2, (n1 * r2 - n * r21) / (r2 * r2))


def _select(args, pick_max: bool) -> Jet:
    out = args[0]
    for a in args[1:]:
        take = (a.f > out.f) if pick_max else (a.f < out.f)
        out = Jet(np.where(take, a.f, out.f), np.where(take, a.d, out.d),
                  np.where(take, a.dd, out.dd))
    return out


class _JetEvaluator:
    def __init__(self, t):
        self.t = Jet(t, np.ones_like(t), np.zeros_like(t))

    def run(self, node) -> Jet:
        if isinstance(node, ast.Expression):
            return self.run(node.body)
        if isinstance(node, ast.Constant):
            return Jet.constant(node.value, self.t.f)
        if isinstance(node, ast.Name):
            if node.id == "t":
                return self.t
            return Jet.constant(CONSTANTS[node.id], self.t.f)
        if isinstance(node, ast.BinOp):
            a, b = self.run(node.left), self.run(node.right)
            op = type(node.op)
            if op is ast.Add:
                return a + b
            if op is ast.Sub:
                return a - b
            if op is ast.Mult:
                return a * b
            if op is ast.Div:
                return a / b
            return a.power(b)
        if isinstance(node, ast.UnaryOp):
            a = self.run(node.operand)
            return -a if isinstance(node.op, ast.USub) else a
        if isinstance(node, ast.Call):
            args = [self.run(a) for a in node.args]
            name = node.func.id
            if name == "atan2":
                return _atan2(*args)
            if name in ("min", "max"):
                return _select(args, name == "max")
            return _unary(name, args[0])
        raise AssertionError(type(node).__name__)  # pragma: no cover


def derivatives(expression, t):
    """Value, first and second derivative of a checked expression in ``t``.

    Parameters
    ----------
    expression : screwkit.pm.Expression
        With the single variable ``t``.
    t : ndarray (N,)

    Returns
    -------
    f, df, ddf : ndarray (N,)

    Raises
    ------
    InputError
        A NaN or infinite value or derivative (``sqrt(t)`` at 0), naming the sample.
    """
    if tuple(expression.variables) != ("t",):
        raise InputError(f"expression {expression.text!r}: a path expression has the one "
                         "variable t")
    t = np.asarray(t, float)
    with np.errstate(all="ignore"):
        j = _JetEvaluator(t).run(expression.tree)
    out = [np.broadcast_to(np.asarray(x, float), t.shape).copy() for x in (j.f, j.d, j.dd)]
    for what, x in zip(("value", "first derivative", "second derivative"), out):
        bad = np.flatnonzero(~np.isfinite(x))
        if bad.size:
            i = int(bad[0])
            raise InputError(f"expression {expression.text!r}: its {what} is not finite at "
                             f"t = {t[i]:.6g} (sample {i})")
    return tuple(out)
