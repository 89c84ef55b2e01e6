"""Fitting: moving the control points. The descent (one Adam loop) and one run at the bottom, strategies
above them, and the public `fit` on top. Imports from every folder above it."""
from ... import threads as _threads  # noqa: F401 - torch's thread count is set before this folder computes
