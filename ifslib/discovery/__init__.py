"""Discovery: a start read from the image. Pattern placement, the automatic start (curve, shape), and
the fractal search for the maps of a fractal. Imports from the folders above it, never from ``fitting``."""
from .. import threads as _threads  # noqa: F401 - torch's thread count is set before this folder computes
