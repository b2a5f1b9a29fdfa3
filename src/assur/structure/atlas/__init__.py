"""Structural (number and type) synthesis: the atlas of planar kinematic chains, their mechanisms and the Assur
groups, with stable canonical IDs (docs/atlas.md)."""
