"""Safe, vectorised arithmetic expressions of design variables and mechanism parameters.

A synthesis problem maps its design variables onto mechanism parameters with expressions such as
``"x0 + r1*cos(theta0)"`` or ``"hypot(rcx, rcy)"``. Names are design variables, mechanism parameters
written as in ``plan.param_names`` (``crank.length``, ``rod.A.distance``: dotted names parse as
attribute chains) and the constants ``pi`` and ``e``. Only arithmetic (+ − * / ** and unary −),
comparisons are not allowed, and the functions of ``FUNCTIONS`` are callable. Everything is evaluated
on numpy arrays (one value per design), in SI units (m, rad).
"""
from __future__ import annotations

import ast
import math

import numpy as np

FUNCTIONS = {
    "sin": np.sin, "cos": np.cos, "tan": np.tan, "asin": np.arcsin, "acos": np.arccos, "atan": np.arctan,
    "atan2": np.arctan2, "hypot": np.hypot, "sqrt": np.sqrt, "abs": np.abs, "exp": np.exp, "log": np.log,
    "radians": np.radians, "degrees": np.degrees, "min": np.minimum, "max": np.maximum,
}
CONSTANTS = {"pi": math.pi, "e": math.e}
_BINARY = {ast.Add: np.add, ast.Sub: np.subtract, ast.Mult: np.multiply, ast.Div: np.divide, ast.Pow: np.power}


class ExpressionError(ValueError):
    """An expression that cannot be parsed or uses something not allowed (message says what)."""


def _dotted(node) -> str | None:
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        head = _dotted(node.value)
        return None if head is None else f"{head}.{node.attr}"
    return None


class Expression:
    """A parsed expression. ``names`` are the variables/parameters it reads; ``__call__(env)``
    evaluates it with ``env`` mapping each name to an array (n,) or a float → array (n,) or float."""

    __slots__ = ("source", "names", "_tree")

    def __init__(self, source: str, known: set[str] | frozenset[str]):
        if not isinstance(source, str) or not source.strip():
            raise ExpressionError(f"must be a non-empty expression string: {source!r}")
        try:
            tree = ast.parse(source.strip(), mode="eval")
        except SyntaxError as exc:
            raise ExpressionError(f"not a valid expression: {source!r} ({exc.msg})") from None
        names: set[str] = set()
        self._check(tree.body, known, names)
        self.source, self.names, self._tree = source, frozenset(names), tree.body

    def _check(self, node, known, names):
        dotted = _dotted(node)
        if dotted is not None:
            if dotted in CONSTANTS:
                return
            if dotted not in known:
                raise ExpressionError(f"unknown name {dotted!r} in {self.source_of(node)!r} "
                                      f"(known: variables, parameters, pi, e)")
            names.add(dotted)
            return
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
            return
        if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
            self._check(node.left, known, names)
            self._check(node.right, known, names)
            return
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            self._check(node.operand, known, names)
            return
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and not node.keywords:
            if node.func.id not in FUNCTIONS:
                raise ExpressionError(f"unknown function {node.func.id!r} (allowed: {', '.join(sorted(FUNCTIONS))})")
            for a in node.args:
                self._check(a, known, names)
            return
        raise ExpressionError(f"not allowed in an expression: {self.source_of(node)!r}")

    @staticmethod
    def source_of(node) -> str:
        try:
            return ast.unparse(node)
        except Exception:  # pragma: no cover - unparse handles every parsed node
            return type(node).__name__

    def __call__(self, env: dict):
        return self._eval(self._tree, env)

    def _eval(self, node, env):
        dotted = _dotted(node)
        if dotted is not None:
            return CONSTANTS[dotted] if dotted in CONSTANTS else env[dotted]
        if isinstance(node, ast.Constant):
            return float(node.value)
        if isinstance(node, ast.BinOp):
            return _BINARY[type(node.op)](self._eval(node.left, env), self._eval(node.right, env))
        if isinstance(node, ast.UnaryOp):
            v = self._eval(node.operand, env)
            return -v if isinstance(node.op, ast.USub) else v
        return FUNCTIONS[node.func.id](*(self._eval(a, env) for a in node.args))

    def __reduce__(self):   # picklable for worker processes: re-parse on the other side
        return (_rebuild, (self.source, tuple(sorted(self.names))))

    def __repr__(self) -> str:
        return f"Expression({self.source!r})"


def _rebuild(source, names):
    return Expression(source, frozenset(names))


__all__ = ["CONSTANTS", "Expression", "ExpressionError", "FUNCTIONS"]
