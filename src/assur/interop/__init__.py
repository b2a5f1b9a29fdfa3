"""L3: exchange with other mechanism tools — pylinkage, PMKS+, Pyslvs and four-bar-rs (docs/interop.md).

``import_mechanism(source, format=None, units=None)`` reads a mechanism another tool wrote — a file path, the text
of a file, a PMKS+ share link, a Pyslvs expression, a pylinkage JSON dict or a live pylinkage object — into an
assur :class:`~assur.model.mechanism.Mechanism` (the format is told from the content where that is unambiguous;
``format`` names it otherwise). What the description cannot carry is a located SpecError or an
:class:`InteropWarning` naming it. ``EXPORTERS`` maps each format a mechanism can be written to onto its writer.
"""
from __future__ import annotations

import importlib
import json
import os
import re
from pathlib import Path

from ..errors import SpecError
from .draft import InteropWarning

#: format → what it reads (its reader: :func:`_reader`)
IMPORTERS = {
    "pylinkage": "pylinkage JSON (Mechanism, legacy joints, hypergraph) or object",
    "pmks": "PMKS+ share link or .pmks file",
    "pyslvs": "Pyslvs YAML project or expression",
    "fourbar": "four-bar-rs RON four-bar",
}
#: format → (the writer, loaded on first use, and the usual file suffix); a writer is ``write(mechanism, path) ->
#: str | None`` (a line to print, e.g. the PMKS+ link). Another format registers with one line here.
EXPORTERS = {
    "pylinkage": (lambda: importlib.import_module("assur.interop.pylinkage_write").write, ".json"),
    "pmks": (lambda: importlib.import_module("assur.interop.pmks").write, ".pmks"),
    "pyslvs": (lambda: importlib.import_module("assur.interop.pyslvs").write, ".pyslvs"),
    "fourbar": (lambda: importlib.import_module("assur.interop.fourbar").write, ".ron"),
}
_LABELS = {"pylinkage": "pylinkage JSON", "pmks": "PMKS+ link", "pyslvs": "Pyslvs expression",
           "fourbar": "four-bar-rs RON"}
_SUFFIX = {".json": "pylinkage", ".pmks": "pmks", ".yml": "pyslvs", ".yaml": "pyslvs", ".pyslvs": "pyslvs",
           ".ron": "fourbar"}
_PMKS_BODY = re.compile(r"^[0-9A-Za-z_-]{1,4}\.[0-9A-Za-z_,-]*\.[0-9A-Za-z_,-]+\.[0-9]{0,8}\.")


def detect_format(text: str, suffix: str = "") -> str:
    """The format of a document's text (``suffix`` of its file decides only where the content does not).
    SpecError when neither tells."""
    t = text.lstrip("\ufeff").strip()
    if t.startswith(("http://", "https://", "pmks2:", "j=")) or _PMKS_BODY.match(t):
        return "pmks"
    if t.startswith("M["):
        return "pyslvs"
    if 'format = "assur/1"' in t or "format='assur/1'" in t.replace(" ", ""):
        raise SpecError([("format", "this is already an assur/1 mechanism file: open it directly")])
    if t.startswith("{"):
        try:
            json.loads(t)
            return "pylinkage"
        except ValueError:
            pass
    if re.search(r"\bp1x\s*:|\bp1i\s*:|\box\s*:", t) and "(" in t:
        return "fourbar"
    if re.search(r"^\s*mechanism\s*:", t, re.M) or re.search(r"[{,]\s*mechanism\s*:", t):
        return "pyslvs"
    if suffix.lower() in _SUFFIX:
        return _SUFFIX[suffix.lower()]
    raise SpecError([("", "cannot tell the format: not a pylinkage JSON, a PMKS+ link or .pmks file, a Pyslvs "
                          "project or expression, nor a four-bar-rs RON file; name it with --format")])


def _text(source) -> tuple[str, str, str]:
    """(text, suffix, label) of a path or of the text itself."""
    from ..io.toml_reader import read_text
    if isinstance(source, bytes):
        source = source.decode("utf-8", errors="replace")
    if isinstance(source, Path) or (isinstance(source, str) and "\n" not in source and len(source) < 4096
                                    and not source.startswith(("http://", "https://", "M[", "{", "("))
                                    and os.path.exists(source)):
        return read_text(source), Path(source).suffix, str(source)
    if isinstance(source, str):
        if ("\n" not in source and len(source) < 4096 and Path(source).suffix.lower() in {*_SUFFIX, ".toml", ".txt"}
                and not source.startswith(("http://", "https://"))):
            raise SpecError([("", f"no such file: {source}")])
        if len(source) > 16 * 2 ** 20:
            raise SpecError([("", "a document larger than 16 MiB is not a mechanism drawing")])
        return source, "", "the given text"
    raise SpecError([("", f"cannot import a {type(source).__name__}: give a file, its text, a link, a dict or a "
                          "pylinkage object")])


def draft_of(source, format: str | None = None, units: str | None = None):  # noqa: A002 - the public keyword
    """The :class:`~assur.interop.draft.Draft` of ``source`` (see :func:`import_mechanism`)."""
    from . import pylinkage_read as pl
    if format is not None and format not in IMPORTERS:
        raise SpecError([("--format", f"must be one of {', '.join(IMPORTERS)}: {format!r}")])
    if pl.is_live(source):
        return pl.read_live(source, units)
    if isinstance(source, dict):
        if format in (None, "pylinkage") and pl.kind_of(source):
            return _pylinkage_dict(source, units)
        if format in (None, "pyslvs") and isinstance(source.get("mechanism"), str):
            from . import pyslvs
            return pyslvs.read(json.dumps(source), units)
        raise SpecError([("", f"a dict that is not a pylinkage mechanism (keys: {', '.join(map(str, source))[:200]})")])
    text, suffix, label = _text(source)
    fmt = format or detect_format(text, suffix)
    if label == "the given text":
        label = _LABELS[fmt]
    try:
        if fmt == "pylinkage":
            try:
                data = json.loads(text)
            except ValueError as exc:
                raise SpecError([("", f"not JSON: {exc}")]) from None
            return _pylinkage_dict(data, units)
        return _reader(fmt)(text, units)
    except SpecError as exc:
        if exc.source is None:
            raise SpecError(exc.problems, label) from None
        raise


def _reader(fmt: str):
    """The ``read(text, units) -> Draft`` of a text format."""
    if fmt == "pmks":
        from .pmks import read
    elif fmt == "pyslvs":
        from .pyslvs import read
    else:
        from .fourbar import read
    return read


def _pylinkage_dict(data, units):
    from . import pylinkage_read as pl
    kind = pl.kind_of(data)
    if kind is None:
        keys = ", ".join(map(str, data)) if isinstance(data, dict) else type(data).__name__
        raise SpecError([("", f"a JSON document that is not a pylinkage mechanism (its keys: {keys[:200]}); "
                              "pylinkage's have 'joints' and 'links'")])
    return {"modern": pl.read_modern, "legacy": pl.read_legacy, "hypergraph": pl.read_hypergraph}[kind](data, units)


def import_mechanism(source, format: str | None = None, units: str | None = None):  # noqa: A002
    """The assur Mechanism of a design another tool wrote (see the module docstring). ``units``: the length
    unit of a unitless source (pylinkage, Pyslvs, four-bar-rs; default m). Raises SpecError (located) or
    StructureError; warns (:class:`InteropWarning`) for what the description does not carry."""
    return draft_of(source, format, units).build()


def export_mechanism(mechanism, format: str, path):  # noqa: A002
    """Write ``mechanism`` in ``format`` (a key of :data:`EXPORTERS`) to ``path``; returns the writer's message."""
    if format not in EXPORTERS:
        raise SpecError([("--to", f"must be one of {', '.join(EXPORTERS)}: {format!r}")])
    return EXPORTERS[format][0]()(mechanism, path)


__all__ = ["EXPORTERS", "IMPORTERS", "InteropWarning", "detect_format", "draft_of", "export_mechanism",
           "import_mechanism"]
