"""docs/reproduction.md must equal what docs/reproduction.py computes now (it never goes stale)."""
import runpy
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_reproduction_document_is_current():
    generate = runpy.run_path(str(ROOT / "docs" / "reproduction.py"))["generate"]
    assert (ROOT / "docs" / "reproduction.md").read_text(encoding="utf-8") == generate(), \
        "docs/reproduction.md is stale: run python docs/reproduction.py"
