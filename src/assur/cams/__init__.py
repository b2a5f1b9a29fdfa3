"""Cams: motion laws, followers, conjugate profiles, pressure angles, curvature and sizing (docs/cams.md).

- :mod:`.laws`: lift programs (dwell, harmonic, cycloidal, modified trapezoid, modified sine, 3-4-5 and 4-5-6-7
  polynomials, periodic C² splines), SVAJ diagrams, continuity (the fundamental law of cam design);
- :mod:`.geometry`: a cam and its follower, the contact by conjugate geometry (profile, pitch curve, pressure angle,
  radii of curvature, undercut);
- :mod:`.followers`: translating (in-line, offset) and oscillating followers, knife-edge, roller and flat-faced, by
  hand or from a mechanism's ``[[cams]]`` pair;
- :mod:`.sizing`: the smallest base circle for a largest pressure angle and curvature limits;
- :mod:`.outline`: the cam plate's outline (mm, cam frame) and its DXF/SVG drawing;
- :mod:`.mechanism`: a mechanism's cam pairs over a solved run (contact forces use it).
"""
