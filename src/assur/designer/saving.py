"""Saving the designer's document into its file, changing only what the edits changed.

The designer edits a normalised document (:func:`assur.io.mechanism_writer.as_dict` of the file, plus its
``[style]``); the file itself has comments, an order, quantities with units (``mass = "0.6358 kg"``) and a layout
that the normalised document does not keep. :func:`updated_text` compares the document the file was read as with
the document to save, key by key, and writes only the values that differ into the file's own text, parsed by
tomlkit (a format-preserving TOML library): every comment, blank line, unit string and value the edits did not
touch stays byte for byte. A value whose table has another shape in the file (a link written as a list of points
that gained a ``length``, say) is replaced as a whole entry. The result is checked: it must load to the document
to save (else the next coarser replacement is tried, down to a whole rewrite, which always loads).
"""
from __future__ import annotations

_MISSING = object()


def canonical(doc: dict) -> dict:
    """The document as the file reader and writer see it (``as_dict(from_dict(doc))`` and its ``[style]``): two
    documents that load to the same mechanism and style have equal canonical forms."""
    import warnings

    from ..io.mechanism_file import from_dict
    from ..io.mechanism_writer import as_dict
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        out = as_dict(from_dict(doc, source="the designer's document"))
    if isinstance(doc.get("style"), dict):
        out["style"] = doc["style"]
    return out


def _item(value):
    """A tomlkit value of a plain one: tables inline (a value inside a table), arrays on one line."""
    import tomlkit
    if isinstance(value, dict):
        t = tomlkit.inline_table()
        for k, v in value.items():
            t[k] = _item(v)
        return t
    if isinstance(value, (list, tuple)):
        a = tomlkit.array()
        for v in value:
            a.append(_item(v))
        return a
    return tomlkit.item(value)


def _table_item(value, inline: bool):
    """``value`` (a dict, or a list of dicts) as a tomlkit table (or array of tables) unless ``inline``."""
    import tomlkit
    if inline:
        return _item(value)
    if isinstance(value, dict):
        t = tomlkit.table()
        for k, v in value.items():
            t[k] = _table_item(v, inline=not (isinstance(v, dict) and any(isinstance(x, dict) for x in v.values())))
        return t
    aot = tomlkit.aot()
    for entry in value:
        aot.append(_table_item(entry, inline=False))
    return aot


def _is_inline(container) -> bool:
    import tomlkit.items as ti
    return isinstance(container, (ti.InlineTable, ti.Array))


def _set(container, key, value) -> None:
    """``container[key] = value`` keeping the old value's comment and the container's style."""
    import tomlkit.items as ti
    old = container.get(key, None) if hasattr(container, "get") else container[key]
    inline = _is_inline(container) or not (isinstance(value, dict) and any(isinstance(v, dict) for v in value.values())
                                           or isinstance(value, list) and value and all(isinstance(v, dict)
                                                                                         for v in value))
    if isinstance(old, (ti.Table, ti.AoT)) and not _is_inline(container):
        inline = False
    new = _table_item(value, inline) if isinstance(value, (dict, list)) else _item(value)
    if old is not None and isinstance(old, ti.Item) and isinstance(new, ti.Item) and not isinstance(old, ti.Table):
        trivia = getattr(old, "trivia", None)
        if trivia is not None and getattr(new, "trivia", None) is not None:
            new.trivia.comment = trivia.comment
            new.trivia.comment_ws = trivia.comment_ws
            new.trivia.trail = trivia.trail
    container[key] = new


def _apply(raw, old, new, depth: int, limit: int) -> None:
    """Write into ``raw`` (a tomlkit container holding ``old``) the differences of ``new`` from ``old``: recursing
    into tables and arrays of tables of the same shape down to ``limit`` levels, replacing below it."""
    for key in [k for k in old if k not in new]:
        if key in raw:
            del raw[key]
    for key, value in new.items():
        before = old.get(key, _MISSING)
        if before == value:
            continue
        here = raw.get(key, _MISSING) if hasattr(raw, "get") else _MISSING
        if depth < limit and here is not _MISSING:
            if isinstance(value, dict) and isinstance(before, dict) and hasattr(here, "items"):
                _apply(here, before, value, depth + 1, limit)
                continue
            if _tables(value) and _tables(before) and len(value) == len(before) and _same_length_tables(here, value):
                for r, o, n in zip(here, before, value):
                    _apply(r, o, n, depth + 1, limit)
                continue
        _set(raw, key, value)


def _tables(x) -> bool:
    return isinstance(x, list) and bool(x) and all(isinstance(v, dict) for v in x)


def _same_length_tables(raw, value) -> bool:
    try:
        return len(raw) == len(value) and all(hasattr(r, "items") for r in raw)
    except TypeError:
        return False


def updated_text(text: str, old: dict, new: dict) -> str:
    """The file ``text`` (which loads to document ``old``) changed to load to document ``new``, keeping everything
    else of the text (see the module docstring). ``old`` and ``new`` are canonical documents."""
    import tomlkit

    from ..io.toml_reader import parse_toml
    from ..io.toml_writer import dumps
    want = canonical(new)
    for limit in (32, 2, 1):
        try:
            raw = tomlkit.parse(text)
            _apply(raw, old, new, 0, limit)
            out = tomlkit.dumps(raw)
            if canonical(parse_toml(out)) == want:
                return out
        except Exception:   # noqa: BLE001 - a shape tomlkit cannot hold: the next coarser replacement
            continue
    return dumps(new)


__all__ = ["canonical", "updated_text"]
