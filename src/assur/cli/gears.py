"""CLI commands of this area (being built): registered into the main parser by `register(sub)`."""
from __future__ import annotations


def register(sub) -> None:
    """Add this module's sub-commands to the argparse sub-parsers `sub`."""
