"""Spatial plans (the vector method of paper 003): compile, step executors, the numpy backend."""
