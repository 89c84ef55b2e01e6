"""Raster: from the leaves to pixels. The exact nearest-leaf search, the distance field with its
gradient, and the rendering. Imports from ``geometry`` only."""
from ... import threads as _threads  # noqa: F401 - torch's thread count is set before this folder computes
