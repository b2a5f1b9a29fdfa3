"""Planar plans: compile, geometry, step executors, the numpy and numba backends."""
