"""Scoring: how close a drawing is to a target. Losses for fitting, mask metrics and `evaluate` for
judging, the collage distance. Imports from ``geometry``, ``raster`` and ``targets``."""
