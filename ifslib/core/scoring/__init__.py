"""Scoring: how close a drawing is to a target. Losses for fitting, mask metrics and `evaluate` for
judging, the collage distance. Imports from ``geometry``, ``raster`` and ``targets``."""
from ... import threads as _threads  # noqa: F401 - torch's thread count is set before this folder computes
