"""``assur report``: one self-contained HTML page per mechanism."""
from __future__ import annotations

from .html import build_report, write_report

__all__ = ["build_report", "write_report"]
