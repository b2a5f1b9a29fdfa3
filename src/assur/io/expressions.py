"""Safe, vectorised arithmetic expressions, as written in the toolkit's files.

A synthesis problem maps its design variables onto mechanism parameters with expressions such as
``"x0 + r1*cos(theta0)"`` or ``"hypot(rcx, rcy)"``; a gear-pair file gives its speed ratio as an expression of the
driving angle, ``"1 + 0.3*cos(phi)"``. An expression may use numbers, the names it is given (dotted names such as
``crank.length`` or ``rod.A.distance`` parse as attribute chains where ``attributes=True``), the constants ``pi``
and ``e``, the operators + − * / ** and unary −, and the functions of ``FUNCTIONS`` (or the subset it is given).
Nothing else parses: no comparisons, subscripts, keywords or other calls. Evaluation works on numpy arrays (one
value per design or per sample).
"""
from __future__ import annotations

import ast
import math

import numpy as np

from ..errors import ExpressionError

#: the callable functions: name → (numpy function, number of arguments)
FUNCTIONS = {
    "sin": (np.sin, 1), "cos": (np.cos, 1), "tan": (np.tan, 1), "asin": (np.arcsin, 1), "acos": (np.arccos, 1),
    "atan": (np.arctan, 1), "atan2": (np.arctan2, 2), "hypot": (np.hypot, 2), "sqrt": (np.sqrt, 1),
    "abs": (np.abs, 1), "exp": (np.exp, 1), "log": (np.log, 1), "radians": (np.radians, 1),
    "degrees": (np.degrees, 1), "min": (np.minimum, 2), "max": (np.maximum, 2),
}
CONSTANTS = {"pi": math.pi, "e": math.e}
_BINARY = {ast.Add: np.add, ast.Sub: np.subtract, ast.Mult: np.multiply, ast.Div: np.divide, ast.Pow: np.power}


def _dotted(node, attributes: bool) -> str | None:
    if isinstance(node, ast.Name):
        return node.id
    if attributes and isinstance(node, ast.Attribute):
        head = _dotted(node.value, attributes)
        return None if head is None else f"{head}.{node.attr}"
    return None


def _text(node) -> str:
    try:
        return ast.unparse(node)
    except Exception:  # pragma: no cover - unparse handles every parsed node
        return type(node).__name__


class Expression:
    """A parsed expression. ``names`` are the known names it reads; ``__call__(env)`` evaluates it.

    source: the text; known: the names it may read; functions: the names of the callable functions (default all
    of ``FUNCTIONS``); attributes: whether dotted names are names (else ``a.b`` is not allowed). Raises
    ExpressionError naming what is not allowed. Picklable (re-parsed on the other side)."""

    __slots__ = ("source", "names", "functions", "attributes", "_tree")

    def __init__(self, source: str, known, *, functions=None, attributes: bool = True):
        self.functions = tuple(sorted(FUNCTIONS if functions is None else functions))
        self.attributes = bool(attributes)
        if not isinstance(source, str) or not source.strip():
            raise ExpressionError(f"must be a non-empty expression string: {source!r}")
        try:
            tree = ast.parse(source.strip(), mode="eval")
        except SyntaxError as exc:
            raise ExpressionError(f"not a valid expression: {source!r} ({exc.msg})") from None
        names: set[str] = set()
        self._check(tree.body, frozenset(known), names)
        self.source, self.names, self._tree = source, frozenset(names), tree.body

    def _check(self, node, known, names):
        dotted = _dotted(node, self.attributes)
        if dotted is not None:
            if dotted in CONSTANTS:
                return
            if dotted not in known:
                shown = ", ".join([*sorted(known)[:12], *(["…"] if len(known) > 12 else []), *CONSTANTS])
                raise ExpressionError(f"unknown name {dotted!r}: not allowed in an expression (known: {shown})")
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
            if node.func.id not in self.functions:
                raise ExpressionError(f"unknown function {node.func.id!r}: not allowed in an expression (allowed: "
                                      f"{', '.join(self.functions)})")
            arity = FUNCTIONS[node.func.id][1]
            if len(node.args) != arity:
                raise ExpressionError(f"{node.func.id}() takes {arity} argument{'s' if arity > 1 else ''}: "
                                      f"{_text(node)!r}")
            for a in node.args:
                self._check(a, known, names)
            return
        raise ExpressionError(f"not allowed in an expression: {_text(node)!r} (use numbers, names, + - * / ** and "
                              f"the functions {', '.join(self.functions)})")

    def __call__(self, env: dict, shape=None):
        """The value: env maps each name to an array (n,) or a float → array (n,) or float.

        ``shape``: when given, numbers and constants enter as arrays of this shape (so every operation works
        element by element on arrays of one shape); else as Python floats."""
        return self._eval(self._tree, env, shape)

    def _eval(self, node, env, shape):
        dotted = _dotted(node, self.attributes)
        if dotted is not None:
            if dotted in CONSTANTS:
                return CONSTANTS[dotted] if shape is None else np.full(shape, CONSTANTS[dotted])
            return env[dotted]
        if isinstance(node, ast.Constant):
            return float(node.value) if shape is None else np.full(shape, float(node.value))
        if isinstance(node, ast.BinOp):
            return _BINARY[type(node.op)](self._eval(node.left, env, shape), self._eval(node.right, env, shape))
        if isinstance(node, ast.UnaryOp):
            v = self._eval(node.operand, env, shape)
            return -v if isinstance(node.op, ast.USub) else v
        return FUNCTIONS[node.func.id][0](*(self._eval(a, env, shape) for a in node.args))

    def __reduce__(self):   # picklable for worker processes: re-parse on the other side
        return (_rebuild, (self.source, tuple(sorted(self.names)), self.functions, self.attributes))

    def __repr__(self) -> str:
        return f"Expression({self.source!r})"


def _rebuild(source, names, functions, attributes):
    return Expression(source, frozenset(names), functions=functions, attributes=attributes)


def function_of(text: str, variable: str, *, functions=None):
    """A vectorised function ``f(x)`` of one variable from an expression in ``variable`` (no dotted names).

    f maps an array (...) to an array of the same shape; numbers in the expression enter as arrays of that
    shape. Raises ExpressionError naming what is not allowed."""
    expr = Expression(text, {variable}, functions=functions, attributes=False)

    def evaluate(x):
        x = np.asarray(x, dtype=float)
        return expr({variable: x}, shape=np.shape(x))

    return evaluate


__all__ = ["CONSTANTS", "Expression", "ExpressionError", "FUNCTIONS", "function_of"]
