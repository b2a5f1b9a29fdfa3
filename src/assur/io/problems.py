"""Problems found while reading a document, gathered so that every one is reported at once.

A reader adds ``(path, message)`` pairs as it goes (``path`` names the field, e.g. ``links.coupler[2]``) and
raises them together as one :class:`~assur.errors.SpecError` at the end.
"""
from __future__ import annotations

from ..errors import SpecError


class Problems:
    """An ordered list of ``(path, message)`` problems; ``items`` holds them."""

    __slots__ = ("items",)

    def __init__(self):
        self.items: list[tuple[str, str]] = []

    def add(self, path: str, message: str) -> None:
        """Record one problem at ``path``."""
        self.items.append((path, message))

    def extend(self, problems) -> None:
        """Record several ``(path, message)`` problems."""
        self.items.extend(problems)

    def section(self, data, key: str, message: str = "must be a table", kind: type = dict):
        """``data[key]`` when it is a ``kind`` (dict: a TOML table; list: an array of tables), an empty one when
        absent; when it is something else, the problem ``message`` at ``key`` and an empty one."""
        value = data.get(key, kind())
        if not isinstance(value, kind):
            self.add(key, message)
            return kind()
        return value

    def unknown_keys(self, table, allowed, path: str = "") -> bool:
        """Record each key of ``table`` that is not in ``allowed`` as a problem at ``path.key`` (at ``key`` for
        the top level), naming the allowed keys in the order given. Returns whether there was any."""
        unknown = [k for k in table if k not in allowed]
        for k in unknown:
            self.add(f"{path}.{k}" if path else k, f"unknown key (allowed: {', '.join(allowed)})")
        return bool(unknown)

    def __bool__(self) -> bool:
        return bool(self.items)

    def __len__(self) -> int:
        return len(self.items)

    def error(self, source: str | None = None) -> SpecError:
        """The problems as one SpecError (of the document ``source``)."""
        return SpecError(self.items, source)

    def raise_if_any(self, source: str | None = None) -> None:
        """Raise the problems as one SpecError when there is any."""
        if self.items:
            raise self.error(source)


__all__ = ["Problems"]
