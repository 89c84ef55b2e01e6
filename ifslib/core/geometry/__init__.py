"""Geometry: the IFS itself, its leaves to depth K and its attractor's, named patterns, the ``ifslib/1`` file."""
from ... import threads as _threads  # noqa: F401 - torch's thread count is set before this folder computes
