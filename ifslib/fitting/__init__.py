"""Fitting: the inverse problem. Targets, losses, initial points, one Adam run at the bottom,
batched runs beside it, strategies above them, and the public `fit` on top; metrics and the
parameter sweep. Imports from ``geometry`` and ``raster``."""
