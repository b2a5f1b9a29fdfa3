"""Deprecated: the expressions of synthesis problems are :mod:`assur.io.expressions`.

Kept for one release so that ``from assur.synthesis.expressions import Expression`` keeps working; importing it
warns with a ``DeprecationWarning`` naming the new place. Nothing inside the package imports it.
"""
import warnings

from ..io.expressions import CONSTANTS, FUNCTIONS, Expression, ExpressionError

warnings.warn("assur.synthesis.expressions is deprecated: import from assur.io.expressions (Expression, "
              "ExpressionError, FUNCTIONS, CONSTANTS)", DeprecationWarning, stacklevel=2)

__all__ = ["CONSTANTS", "Expression", "ExpressionError", "FUNCTIONS"]
