"""Raster: from the leaves to pixels. The exact nearest-leaf search, the distance field with its
gradient, and the rendering. Imports from ``geometry`` only."""
