"""Geometry: the IFS itself (control points, rules, primitives), its leaves to depth K, named
patterns, the ``ifslib/1`` JSON file, and a curve's self-crossings. Imports nothing else of ifslib
but the top-level helpers."""
from ... import threads as _threads  # noqa: F401 - torch's thread count is set before this folder computes
