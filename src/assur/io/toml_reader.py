"""Reading the toolkit's TOML documents (mechanism, gear pair, wheel-step, synthesis problem) as dicts.

Failures are SpecErrors that name the file: a missing or unreadable file, a file larger than
``MAX_FILE_BYTES`` (an endless stream such as ``/dev/zero`` is refused, not read until memory runs out),
text that is not valid TOML (with the parser's position), or tables and arrays nested deeper than
``MAX_NESTING``.
"""
from __future__ import annotations

import tomllib
from pathlib import Path

from ..errors import SpecError


#: the largest document read (bytes): every assur document is far smaller
MAX_FILE_BYTES = 16 * 2 ** 20
#: the deepest nesting of tables and arrays accepted (assur documents nest four levels at most)
MAX_NESTING = 32


def read_text(path) -> str:
    """A document's text; SpecError naming the file if it is missing, unreadable or too large."""
    if not isinstance(path, str) and not hasattr(path, "__fspath__") or str(path) == "":
        from ..errors import ArgumentTypeError
        raise ArgumentTypeError([("path", f"must be a file's path (text or a pathlib.Path): {path!r:.60}")])
    path = Path(path)
    try:
        with open(path, "rb") as fh:
            data = fh.read(MAX_FILE_BYTES + 1)
    except FileNotFoundError:
        raise SpecError(f"no such file: {path}") from None
    except OSError as exc:
        raise SpecError(f"cannot read {path}: {exc.strerror or exc}") from None
    if len(data) > MAX_FILE_BYTES:
        raise SpecError(f"cannot read {path}: larger than {MAX_FILE_BYTES // 2 ** 20} MiB (not an assur document)")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise SpecError(f"cannot read {path}: not UTF-8 text ({exc.reason} at byte {exc.start})") from None


def _depth(x, limit: int) -> int:
    """Nesting depth of dicts and lists, stopping once past ``limit``."""
    if limit < 0 or not isinstance(x, (dict, list)):
        return 0
    items = x.values() if isinstance(x, dict) else x
    return 1 + max((_depth(v, limit - 1) for v in items), default=0)


def parse_toml(text: str, source: str | None = None) -> dict:
    """TOML text as a dict; SpecError (of the document ``source``) with the parser's position if it is not
    valid TOML."""
    if not isinstance(text, str):
        from ..errors import ArgumentTypeError
        hint = " (decode bytes first: data.decode('utf-8'))" if isinstance(text, (bytes, bytearray)) else ""
        raise ArgumentTypeError([("text", f"must be the document's TOML text (str), not {type(text).__name__}"
                                          f"{hint}")], source)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SpecError([("", f"not valid TOML: {exc}")], source) from None
    except RecursionError:
        data = None
    if data is None or _depth(data, MAX_NESTING) > MAX_NESTING:
        raise SpecError([("", f"tables or arrays nested deeper than {MAX_NESTING} levels")], source)
    return data


def read_toml(path) -> dict:
    """Any assur TOML document (mechanism, gears, wheel-step, synthesis problem) as a dict;
    SpecError with the file and the parser's position if it is not valid TOML."""
    return parse_toml(read_text(path), str(path))


__all__ = ["MAX_FILE_BYTES", "MAX_NESTING", "parse_toml", "read_text", "read_toml"]
