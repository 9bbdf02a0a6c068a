"""Safe math expressions of one variable ``x``, with exact symbolic derivatives.

User text is never evaluated by Python: it is parsed into Python's syntax tree
(:func:`ast.parse`, which does not execute anything), every node is checked against a
whitelist, and the tree is rebuilt from camgen's own node classes, which evaluate with numpy
and differentiate symbolically.

Allowed: numbers, ``x``, ``pi``, ``+ - * / **``, unary ``-``/``+``, parentheses and the
functions ``sin cos tan exp log sqrt abs``.  Anything else raises
:class:`~camgen.errors.ParameterError` naming the offending token.

The work is bounded before it is done: at most :data:`MAX_LENGTH` characters, operations and
calls nested at most :data:`MAX_DEPTH` levels (checked on the syntax tree without recursion,
before anything recurses on it), and at most :data:`MAX_NODES` operations in the expression and in
each of its derivatives, each measured before the next is built (a product of n factors has a
second derivative of O(n^3) operations); a number beyond the float range is refused.
"""
from __future__ import annotations

import ast
import math
from dataclasses import dataclass
from typing import TypeAlias

import numpy as np

from camgen.errors import ParameterError

__all__ = [
    "Bin", "Const", "Expression", "FUNCTIONS", "Func", "MAX_DEPTH", "MAX_DERIVED_DEPTH", "MAX_LENGTH", "MAX_NODES",
    "Node", "ONE", "Value", "Var", "ZERO", "add", "div", "mul", "neg", "parse_expression", "power", "sub",
]

#: Longest expression, characters.
MAX_LENGTH = 2000
#: Deepest nesting of operations and calls (a sum of n terms nests n levels: the length limit
#: allows about 100 terms of a Fourier series).
MAX_DEPTH = 100
#: Most operations evaluated for the expression and for each of its two derivatives (shared
#: subexpressions counted each time they are evaluated), and deepest nesting of a derivative:
#: evaluating and differentiating recurse once per level.
MAX_NODES = 20_000
MAX_DERIVED_DEPTH = 4 * MAX_DEPTH
FUNCTIONS = ("sin", "cos", "tan", "exp", "log", "sqrt", "abs")
_ALLOWED = "numbers, x, pi, + - * / **, parentheses and sin cos tan exp log sqrt abs"
#: What a node evaluates to: an array, or a numpy scalar for a constant part (and for a 0-d x:
#: numpy's ufuncs return scalars there).
Value: TypeAlias = "np.ndarray | np.float64"


class Node:
    """A node of an expression tree; evaluate with :meth:`__call__`, differentiate with :meth:`diff`."""

    def __call__(self, x: np.ndarray) -> Value:  # pragma: no cover - abstract
        raise NotImplementedError

    def diff(self) -> "Node":  # pragma: no cover - abstract
        raise NotImplementedError


@dataclass(frozen=True)
class Const(Node):
    value: float

    def __call__(self, x: np.ndarray) -> Value:
        return np.float64(self.value)  # a scalar: numpy broadcasting spreads it (see Expression)

    def diff(self) -> Node:
        return ZERO

    def __str__(self) -> str:
        return repr(self.value)


@dataclass(frozen=True)
class Var(Node):
    def __call__(self, x: np.ndarray) -> Value:
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

    def __call__(self, x: np.ndarray) -> Value:
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

    def __call__(self, x: np.ndarray) -> Value:
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
        try:
            value = float(node.value)
        except OverflowError:  # an integer beyond the float range (2**1024)
            value = math.inf
        if not math.isfinite(value):
            raise ParameterError("expression", text, f"finite numbers ({_ALLOWED})", "a number beyond the float range")
        return Const(value)
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
    """A node evaluated to an array of the input's shape (a constant node's scalar spread over it)."""

    def __init__(self, node: Node) -> None:
        self.node = node

    def __call__(self, x: np.ndarray) -> np.ndarray:
        value = self.node(x)
        shape = np.shape(x)
        if isinstance(value, np.ndarray) and value.shape == shape:
            return value
        return np.broadcast_to(value, shape).copy()


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


def _syntax_depth(tree: ast.AST) -> int:
    """The nesting depth of a syntax tree, counted without recursion."""
    deepest = 0
    todo = [(tree, 1)]
    while todo:
        node, level = todo.pop()
        deepest = max(deepest, level)
        todo.extend((child, level + 1) for child in ast.iter_child_nodes(node) if not isinstance(child, (ast.expr_context, ast.operator)))
    return deepest


def _work(node: Node) -> tuple[int, int]:
    """(depth, operations evaluated) of an expression tree whose subtrees may be shared, without
    recursion: each node once, its operation count that of its children plus one."""
    measured: dict[int, tuple[int, int]] = {}
    todo: list[tuple[Node, bool]] = [(node, False)]
    while todo:
        item, children_done = todo.pop()
        if id(item) in measured:
            continue
        children = [c for c in (getattr(item, "left", None), getattr(item, "right", None), getattr(item, "arg", None)) if c is not None]
        if children_done:
            parts = [measured[id(c)] for c in children]
            measured[id(item)] = (1 + max((p[0] for p in parts), default=0), 1 + sum(p[1] for p in parts))
        else:
            todo.append((item, True))
            todo.extend((c, False) for c in children)
    return measured[id(node)]


def _bounded(node: Node, what: str, text: str) -> Node:
    """``node`` if evaluating it (and differentiating it next) stays within :data:`MAX_NODES`
    operations and :data:`MAX_DERIVED_DEPTH` levels, else a ParameterError."""
    depth, operations = _work(node)
    if operations > MAX_NODES or depth > MAX_DERIVED_DEPTH:
        raise ParameterError("expression", text, _LIMITS,
                             f"{what} takes {operations} operations nested {depth} levels deep")
    return node


_LIMITS = (f"an expression of at most {MAX_LENGTH} characters, {MAX_DEPTH} levels of nested operations and calls, "
           f"and at most {MAX_NODES} operations in it and in each of its first two derivatives")


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
    except (ValueError, RecursionError, MemoryError):  # NUL characters; nesting Python's parser cannot take
        raise ParameterError("expression", text, _LIMITS, "Python's parser cannot read it") from None
    depth = _syntax_depth(tree) - 1  # the Expression wrapper is not a level
    if depth > MAX_DEPTH:
        raise ParameterError("expression", text, _LIMITS, f"operations and calls nested {depth} levels deep")
    f = _bounded(_convert(tree, text), "the expression", text)
    df = _bounded(f.diff(), "its first derivative", text)
    d2f = _bounded(df.diff(), "its second derivative", text)
    return Expression(text, _Vectorised(f), _Vectorised(df), _Vectorised(d2f))
