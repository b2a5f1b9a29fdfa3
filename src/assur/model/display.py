"""Small HTML tables for notebooks: the ``_repr_html_`` of mechanisms, states and results.

Pure formatting (standard library and numpy only), so every layer can use it. Every name and value is
HTML-escaped; numbers are shown with six significant digits, arrays by shape and range.
"""
from __future__ import annotations

import dataclasses
import html
import math
from typing import Iterable

import numpy as np

_STYLE = ("border-collapse:collapse;font-size:0.9em;text-align:left")


def fmt(value, unit: str = "") -> str:
    """A short, plain-text rendering of a value (not escaped): 6 significant digits for numbers,
    ``array (shape) min … max`` for arrays, ``a, b, c`` for short sequences."""
    suffix = f" {unit}" if unit else ""
    if value is None:
        return "–"
    if isinstance(value, (bool, np.bool_)):
        return "yes" if value else "no"
    if isinstance(value, (int, np.integer)):
        return f"{int(value)}{suffix}"
    if isinstance(value, (float, np.floating)):
        v = float(value)
        return (f"{v:.6g}" if math.isfinite(v) else str(v)) + suffix
    if isinstance(value, np.ndarray):
        if value.ndim == 0:
            return fmt(value.item(), unit)
        if value.size <= 6 and value.ndim == 1:
            return "[" + ", ".join(fmt(v) for v in value) + "]" + suffix
        shape = " × ".join(map(str, value.shape))
        if np.issubdtype(value.dtype, np.number) and not np.iscomplexobj(value):
            finite = value[np.isfinite(value)]
            if finite.size:
                return f"array ({shape}), {fmt(finite.min())} … {fmt(finite.max())}{suffix}"
        return f"array ({shape})"
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return ", ".join(f"{f.name} {fmt(getattr(value, f.name))}" for f in dataclasses.fields(value)) + suffix
    if isinstance(value, dict):
        return ", ".join(f"{k}: ({fmt(v)})" if isinstance(v, dict) else f"{k}: {fmt(v)}"
                         for k, v in value.items()) + suffix
    if isinstance(value, (tuple, list)):
        nested = any(isinstance(v, dict) or dataclasses.is_dataclass(v) for v in value)
        sep = "; " if nested else ", "
        if len(value) > 12:
            return sep.join(fmt(v) for v in value[:12]) + f"{sep}… ({len(value)} in all)"
        return sep.join(fmt(v) for v in value) + suffix
    return str(value) + suffix


def html_table(title: str, rows: Iterable[tuple[str, object]], *, units: dict | None = None) -> str:
    """A two-column HTML table: a bold caption ``title``, then one row per (name, value).
    Values are formatted with :func:`fmt` (``units`` maps a row name to its unit); everything is escaped."""
    units = units or {}
    body = "".join(f"<tr><th style=\"padding:1px 8px\">{html.escape(str(k))}</th>"
                   f"<td style=\"padding:1px 8px\">{html.escape(fmt(v, units.get(k, '')))}</td></tr>"
                   for k, v in rows)
    return (f"<table style=\"{_STYLE}\"><caption style=\"text-align:left;font-weight:bold\">"
            f"{html.escape(title)}</caption>{body}</table>")


def dataclass_table(obj, title: str | None = None, *, units: dict | None = None, skip=()) -> str:
    """:func:`html_table` of a dataclass's fields (in order, without ``skip``); the title defaults to the
    class name."""
    rows = [(f.name, getattr(obj, f.name)) for f in dataclasses.fields(obj)
            if f.name not in skip and not f.name.startswith("_")]
    return html_table(title or type(obj).__name__, rows, units=units)
