"""Fitting: moving the control points. One Adam run at the bottom, batched runs beside it,
strategies above them, and the public `fit` on top. Imports from every folder above it."""
