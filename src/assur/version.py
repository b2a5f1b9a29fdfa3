"""The version of assur (one place: the package root and every page and file that names it read it)."""
__version__ = "0.1.0"
