"""Everything a person reads: the report pages (``assur report``), the text of the terminal, the solve table,
and the file bundles of gear and wheel-step designs.

page.py holds the pages' skeleton and HTML pieces, text.py the shared text formatters, mechanism.py the
page of a mechanism (planar or spatial), documents.py the pages of design documents, bundles.py the
outputs of ``assur gears`` and ``assur wheelstep``, table.py the table of ``assur solve``.
"""
from __future__ import annotations

from .mechanism import build_report, write_report

__all__ = ["build_report", "write_report"]
