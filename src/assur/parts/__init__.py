"""L3: from a solved cycle to parts a workshop can make (``assur make``, docs/make.md).

- :func:`make_parts` (:mod:`.api`): the parts of a planar mechanism, their conflicts certified over the continuous
  run (:mod:`.conflicts`), the fewest layers by an integer program with its minimality certificate (:mod:`.layers`)
  and the stack (:mod:`.stack`); the result :class:`Parts` builds the solids (:mod:`.solids`, build123d) on demand;
- :mod:`.files` writes STL, 3MF, the STEP assembly, ``parts.json``, ``certificate.json`` and ``bom.csv``;
  :mod:`.page` the HTML page (and :func:`report_section`, its fragment for ``assur report``); :mod:`.massback` the
  mechanism with the parts' masses.

The CAD packages (build123d, trimesh, manifold3d: ``pip install 'assur[make]'``) load only where solids are built.
"""
from .api import LAYERED, Parts, make_parts


def report_section(cycle, **kwargs) -> str:
    """The parts section of ``assur report`` (an HTML fragment) from a solved cycle: :func:`assur.parts.page.report_section`."""
    from .page import report_section as section
    return section(cycle, **kwargs)


__all__ = ["LAYERED", "Parts", "make_parts", "report_section"]
