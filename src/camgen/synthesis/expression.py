"""Safe math expressions of one variable ``x``, with exact symbolic derivatives.

User text is never evaluated by Python: it is parsed into Python's syntax tree
(:func:`ast.parse`, which does not execute anything), every node is checked against a
whitelist, and the tree is rebuilt from camgen's own node classes, which evaluate with numpy
and differentiate symbolically.

Allowed: numbers, ``x``, ``pi``, ``+ - * / **``, unary ``-``/``+``, parentheses and the
functions ``sin cos tan exp log sqrt abs``.  Anything else raises
:class:`~camgen.errors.ParameterError` naming the offending token.
"""
from __future__ import annotations

import ast
import math
from dataclasses import dataclass

import numpy as np

from camgen.errors import ParameterError

MAX_LENGTH = 2000
FUNCTIONS = ("sin", "cos", "tan", "exp", "log", "sqrt", "abs")
_ALLOWED = "numbers, x, pi, + - * / **, parentheses and sin cos tan exp log sqrt abs"


class Node:
    """A node of an expression tree; evaluate with :meth:`__call__`, differentiate with :meth:`diff`."""

    def __call__(self, x: np.ndarray) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    def diff(self) -> "Node":  # pragma: no cover - abstract
        raise NotImplementedError


@dataclass(frozen=True)
class Const(Node):
    value: float

    def __call__(self, x: np.ndarray) -> np.ndarray:
        return np.float64(self.value)  # a scalar: numpy broadcasting spreads it (see Expression)

    def diff(self) -> Node:
        return ZERO

    def __str__(self) -> str:
        return repr(self.value)


@dataclass(frozen=True)
class Var(Node):
    def __call__(self, x: np.ndarray) -> np.ndarray:
        x = np.asarray(x)
        return x if np.iscomplexobj(x) else x.astype(float)  # complex input: complex-step checks

    def diff(self) -> Node:
        return ONE

    def __str__(self) -> str:
        return "x"


ZERO, ONE = Const(0.0), Const(1.0)


def _is(node: Node, value: float) -> bool:
    return isinstance(node, Const) and node.value == value


def add(a: Node, b: Node) -> Node:
    if _is(a, 0.0):
        return b
    if _is(b, 0.0):
        return a
    if isinstance(a, Const) and isinstance(b, Const):
        return Const(a.value + b.value)
    return Bin("+", a, b)


def sub(a: Node, b: Node) -> Node:
    if _is(b, 0.0):
        return a
    if isinstance(a, Const) and isinstance(b, Const):
        return Const(a.value - b.value)
    return Bin("-", a, b)


def mul(a: Node, b: Node) -> Node:
    if _is(a, 0.0) or _is(b, 0.0):
        return ZERO
    if _is(a, 1.0):
        return b
    if _is(b, 1.0):
        return a
    if isinstance(a, Const) and isinstance(b, Const):
        return Const(a.value * b.value)
    return Bin("*", a, b)


def div(a: Node, b: Node) -> Node:
    if _is(a, 0.0):
        return ZERO
    if _is(b, 1.0):
        return a
    return Bin("/", a, b)


def power(a: Node, b: Node) -> Node:
    if _is(b, 1.0):
        return a
    if _is(b, 0.0):
        return ONE
    return Bin("**", a, b)


def neg(a: Node) -> Node:
    if isinstance(a, Const):
        return Const(-a.value)
    return Bin("-", ZERO, a)


@dataclass(frozen=True)
class Bin(Node):
    op: str
    left: Node
    right: Node

    def __call__(self, x: np.ndarray) -> np.ndarray:
        a, b = self.left(x), self.right(x)
        if self.op == "+":
            return a + b
        if self.op == "-":
            return a - b
        if self.op == "*":
            return a * b
        if self.op == "/":
            return a / b
        return np.power(a, b)

    def diff(self) -> Node:
        a, b = self.left, self.right
        da, db = a.diff(), b.diff()
        if self.op == "+":
            return add(da, db)
        if self.op == "-":
            return sub(da, db)
        if self.op == "*":
            return add(mul(da, b), mul(a, db))
        if self.op == "/":
            return div(sub(mul(da, b), mul(a, db)), power(b, Const(2.0)))
        if isinstance(b, Const):  # a ** c
            return mul(mul(Const(b.value), power(a, Const(b.value - 1.0))), da)
        # a ** b = exp(b log a): d = a ** b (db log a + b da / a)
        return mul(self, add(mul(db, Func("log", a)), div(mul(b, da), a)))

    def __str__(self) -> str:
        return f"({self.left} {self.op} {self.right})"


_NUMPY = {"sin": np.sin, "cos": np.cos, "tan": np.tan, "exp": np.exp, "log": np.log, "sqrt": np.sqrt, "abs": np.abs}


@dataclass(frozen=True)
class Func(Node):
    name: str
    arg: Node

    def __call__(self, x: np.ndarray) -> np.ndarray:
        return _NUMPY[self.name](self.arg(x))

    def diff(self) -> Node:
        u, du = self.arg, self.arg.diff()
        outer: Node
        if self.name == "sin":
            outer = Func("cos", u)
        elif self.name == "cos":
            outer = neg(Func("sin", u))
        elif self.name == "tan":
            outer = add(ONE, power(Func("tan", u), Const(2.0)))
        elif self.name == "exp":
            outer = self
        elif self.name == "log":
            outer = div(ONE, u)
        elif self.name == "sqrt":
            outer = div(Const(0.5), self)
        else:  # abs: derivative sign(u), undefined at u = 0
            outer = Bin("/", u, self)
        return mul(outer, du)

    def __str__(self) -> str:
        return f"{self.name}({self.arg})"


def _convert(node: ast.AST, text: str) -> Node:
    if isinstance(node, ast.Expression):
        return _convert(node.body, text)
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
        if not math.isfinite(float(node.value)):
            raise ParameterError("expression", text, f"finite numbers ({_ALLOWED})")
        return Const(float(node.value))
    if isinstance(node, ast.Name):
        if node.id == "x":
            return Var()
        if node.id == "pi":
            return Const(math.pi)
        raise ParameterError("expression", text, _ALLOWED, f"name '{node.id}' is not allowed")
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        inner = _convert(node.operand, text)
        return neg(inner) if isinstance(node.op, ast.USub) else inner
    if isinstance(node, ast.BinOp):
        ops = {ast.Add: add, ast.Sub: sub, ast.Mult: mul, ast.Div: div, ast.Pow: power}
        build = ops.get(type(node.op))
        if build is None:
            symbol = "^ (use ** for powers)" if isinstance(node.op, ast.BitXor) else type(node.op).__name__
            raise ParameterError("expression", text, _ALLOWED, f"operator {symbol} is not allowed")
        left, right = _convert(node.left, text), _convert(node.right, text)
        if build in (add, sub, mul) or (build is power and isinstance(right, Const)):
            return build(left, right)
        return Bin({div: "/", power: "**"}[build], left, right)
    if isinstance(node, ast.Call):
        name = node.func.id if isinstance(node.func, ast.Name) else None
        if name not in FUNCTIONS or len(node.args) != 1 or node.keywords:
            shown = name or ast.unparse(node.func)
            raise ParameterError("expression", text, _ALLOWED, f"call of '{shown}' is not allowed (one argument, whitelisted functions only)")
        return Func(name, _convert(node.args[0], text))
    shown = ast.unparse(node) if hasattr(ast, "unparse") else type(node).__name__
    raise ParameterError("expression", text, _ALLOWED, f"'{shown}' is not allowed")


class _Vectorised:
    """A node evaluated to an array of the input's shape (constant parts come back as scalars)."""

    def __init__(self, node: Node) -> None:
        self.node = node

    def __call__(self, x: np.ndarray) -> np.ndarray:
        value = self.node(x)
        shape = np.shape(x)
        return value if np.shape(value) == shape else np.broadcast_to(value, shape).copy()


@dataclass(frozen=True)
class Expression:
    """A parsed expression ``f(x)`` with its first and second derivatives (each maps an array
    of x to an array of the same shape)."""

    text: str
    f: _Vectorised
    df: _Vectorised
    d2f: _Vectorised

    def __call__(self, x: np.ndarray) -> np.ndarray:
        return self.f(x)


def parse_expression(text: object) -> Expression:
    """Parse ``text`` (e.g. ``"202.4396*sin(pi*x/1000)"``) into an :class:`Expression`.

    Raises
    ------
    ParameterError
        For anything outside the whitelist, naming the offending name, operator or call.
    """
    if not isinstance(text, str) or not text.strip():
        raise ParameterError("expression", text, f"a non-empty string using {_ALLOWED}")
    if len(text) > MAX_LENGTH:
        raise ParameterError("expression", f"<{len(text)} characters>", f"at most {MAX_LENGTH} characters")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:
        raise ParameterError("expression", text, _ALLOWED, f"syntax error at column {exc.offset}") from None
    f = _convert(tree, text)
    df = f.diff()
    return Expression(text, _Vectorised(f), _Vectorised(df), _Vectorised(df.diff()))
