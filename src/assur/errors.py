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


class UnbuildableWarning(UserWarning):
    """Some samples cannot be assembled (issued with ``on_unbuildable='warn'``)."""


class SynthesisError(AssurError, RuntimeError):
    """A synthesis problem cannot be set up or run."""
