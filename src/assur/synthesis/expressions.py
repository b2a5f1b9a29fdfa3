"""The expressions of synthesis problems: :mod:`assur.io.expressions` (re-exported here)."""
from ..io.expressions import CONSTANTS, FUNCTIONS, Expression, ExpressionError

__all__ = ["CONSTANTS", "Expression", "ExpressionError", "FUNCTIONS"]
