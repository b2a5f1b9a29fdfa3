"""L3: file formats and units (TOML mechanism files, CSV tables).

``import_mechanism`` and ``export_mechanism`` (read or write another tool's design: pylinkage, PMKS+, Pyslvs,
four-bar-rs) are those of :mod:`assur.interop`, loaded on first use.
"""


def __getattr__(name):
    if name in ("import_mechanism", "export_mechanism"):
        import importlib
        return getattr(importlib.import_module("assur.interop"), name)
    raise AttributeError(f"module 'assur.io' has no attribute {name!r}")
