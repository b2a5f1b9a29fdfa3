"""Everything a person reads: the report pages (``assur report``), the text of the terminal, the solve table,
and the file bundles of gear and wheel-step designs.

page.py holds the pages' skeleton and HTML pieces, text.py the shared text formatters, mechanism.py the
page of a mechanism (planar or spatial), documents.py the pages of design documents, bundles.py the
outputs of ``assur gears`` and ``assur wheelstep``, table.py the table of ``assur solve``.
"""
from __future__ import annotations

__all__ = ["build_report", "write_report"]


def __getattr__(name: str):
    """``build_report`` and ``write_report`` load the page's modules (the analyses, scipy) on first use, so that
    a command importing only ``report.text`` starts light."""
    if name in __all__:
        from . import mechanism
        return getattr(mechanism, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
