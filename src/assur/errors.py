"""One exception hierarchy for the whole toolkit.

Every error also inherits the matching built-in, so ``except ValueError`` keeps working,
and each is picklable (it is sent across worker processes by the synthesis executors).
"""
from __future__ import annotations


class AssurError(Exception):
    """Base class of every error raised by assur."""


class SpecError(AssurError, ValueError):
    """A mechanism or problem description is invalid.

    ``problems`` lists every problem found as ``(path, message)`` pairs, e.g.
    ``("links.coupler[2]", "unknown point 'Q' (known: A, B, O1)")``.
    """

    def __init__(self, problems, source: str | None = None):
        if isinstance(problems, str):
            problems = [("", problems)]
        self.problems = [(str(p), str(m)) for p, m in problems]
        self.source = source
        super().__init__(self.problems, source)

    def __str__(self) -> str:
        head = f"{self.source}: " if self.source else ""
        lines = [f"{p}: {m}" if p else m for p, m in self.problems]
        if len(lines) == 1:
            return head + lines[0]
        return head + f"{len(lines)} problems\n" + "\n".join("  " + ln for ln in lines)


class ArgumentTypeError(SpecError, TypeError):
    """An argument of the Python API of the wrong kind (a path where a plan belongs, text where numbers do);
    ``problems`` names the argument. Also a TypeError, as Python's own type errors are."""


class UnknownNameError(SpecError, KeyError):
    """A name looked up that the mechanism does not have (a point, a parameter); ``problems`` names the argument
    and lists the known names. Also a KeyError, as a failed look-up is."""

    def __str__(self) -> str:           # SpecError's text, not KeyError's quoted repr
        return SpecError.__str__(self)


def float_array(value, name: str, what: str = "numbers"):
    """``value`` as a float numpy array, or ArgumentTypeError naming the argument ``name`` (text, a mapping or
    ragged lists where numbers belong)."""
    import numpy as np
    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        shown = repr(value)
        shown = shown if len(shown) <= 60 else shown[:57] + "…"
        raise ArgumentTypeError([(name, f"must be {what}: {shown}")]) from None


def one_of(value, allowed) -> bool:
    """True when ``value`` is one of the strings ``allowed`` (False for anything else, arrays included)."""
    return isinstance(value, str) and value in allowed


class StructureError(AssurError, ValueError):
    """The mechanism's structure cannot be decomposed or driven as described."""


class UnbuildableError(AssurError, ArithmeticError):
    """Some samples cannot be assembled (raised with ``on_unbuildable='raise'``)."""

    def __init__(self, message: str, count: int = 0, total: int = 0):
        self.count = count
        self.total = total
        super().__init__(message, count, total)

    def __str__(self) -> str:
        return self.args[0]


class SketchWarning(UserWarning):
    """A mechanism file whose sketch disagrees with its given dimensions (the dimensions are used)."""


class AssumedUnitsWarning(UserWarning):
    """A document without a ``[units]`` table: its numbers are read in the stated default units."""


class UnbuildableWarning(UserWarning):
    """Some samples cannot be assembled (issued with ``on_unbuildable='warn'``)."""


class SynthesisError(AssurError, RuntimeError):
    """A synthesis problem cannot be set up or run."""


class SettingError(SpecError, SynthesisError):
    """A setting of a synthesis run (method, budget, time limit, seed …) given in Python that is not a valid value;
    ``problems`` names the argument. Both a SpecError (located) and a SynthesisError."""


class ExpressionError(SpecError):
    """An arithmetic expression that cannot be parsed or uses something not allowed (the message says what).

    Raised with the message alone; a reader that finds it in a file adds the field's path."""


class GearError(AssurError, ValueError):
    """A transmission law, centre distance or tooth layout cannot make a working gear pair.

    The message names the quantity and the offending angle range, e.g.
    ``pitch radius of the driven gear ≤ 0 for φ ∈ [212.0°, 236.5°]``."""


class OutputError(AssurError, OSError):
    """An output location cannot be used (it is a directory, or its parent does not exist)."""


class MissingPackageError(AssurError, ImportError):
    """An optional package a chosen feature needs is not installed; the message says which and how to install
    it (raised by :func:`require` before the work starts)."""


def require(package: str, feature: str, install: str | None = None):
    """Import the optional ``package`` that ``feature`` needs (e.g. ``"--method cmaes"``), or raise
    MissingPackageError with the install command (default ``pip install PACKAGE``). Returns the module."""
    import importlib
    try:
        return importlib.import_module(package)
    except ImportError as exc:
        detail = "" if getattr(exc, "name", None) == package else f" ({exc})"
        raise MissingPackageError(f"{feature} needs the optional package {package!r}, which cannot be imported"
                                  f"{detail}; install it with: {install or 'pip install ' + package}") from None
