"""L1: structure from connectivity alone (bodies, pairs, mobility, Assur groups); never reads lengths."""
from .graph import Body, Pair, StructureGraph, build_graph
from .assur import AssurGroup, GroupKind, Structure, analyse, mobility_chebyshev, mobility_somov_malyshev

__all__ = ["AssurGroup", "Body", "GroupKind", "Pair", "Structure", "StructureGraph", "analyse", "build_graph",
           "mobility_chebyshev", "mobility_somov_malyshev"]
