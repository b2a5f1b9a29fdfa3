"""What every benchmark script does with its Markdown table: print it, and write it to ``--out`` unless that is
``-``."""
from __future__ import annotations

from pathlib import Path


def publish(lines: list[str], out: str) -> int:
    """Print the table ``lines`` and write them to ``out`` (a path, or ``-`` for none); returns 0."""
    text = "\n".join(lines) + "\n"
    print(text)
    if out != "-":
        Path(out).write_text(text, encoding="utf-8")
    return 0
