"""Structural (number and type) synthesis: the atlas of planar kinematic chains, their mechanisms and the Assur
groups, with stable canonical IDs (docs/atlas.md).

The mathematics only (layer 1: graphs and their canonical forms, imports nothing above ``model`` and
``structure``): nothing here solves, writes or draws. Its faces are :mod:`assur.io.atlas` (each entry as a mechanism
file and a drawing), :mod:`assur.synthesis.legs` (the walking legs dimensioned and ranked by their gait),
:mod:`assur.report.legs` (that ranking as files), :mod:`assur.cli.atlas` and :mod:`assur.cli.legs` (the commands)."""
