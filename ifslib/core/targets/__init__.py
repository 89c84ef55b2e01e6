"""Targets: what the image is. A `Target` (mask, gray levels, distance transform) read from a file,
an array or an IFS; its sizes; the silhouettes the library draws. Imports from ``geometry`` and ``raster``."""
from ... import threads as _threads  # noqa: F401 - torch's thread count is set before this folder computes
