"""The paper's core: geometry (IFS, maps, leaves), raster (nearest leaf, distance, render), targets, scoring and
fitting. It imports no extension of ifslib (tests/test_layers.py)."""
