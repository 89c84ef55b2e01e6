"""Discovery: a start read from the image. Pattern placement, the automatic start (curve, shape), and
the fractal search for the maps of a fractal. Imports from the folders above it, never from ``fitting``."""
