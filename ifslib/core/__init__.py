"""The paper's core: an IFS of control points and symmetry rules, its leaves, the nearest-leaf distance,
the rendering, the paper's losses and the fit loop. It imports no extension of ifslib (tests/test_layers.py).

    geometry/   JSON / pattern -> IFS -> maps -> leaves (and the attractor's certified cut)
    raster/     leaves -> nearest leaf -> distance -> render (and the chaos game)
    targets/    image -> Target (mask, distance transform, sizes)
    scoring/    how close a drawing is: losses, metrics, the collage distance
    fitting/    one Adam run -> strategies -> fit -> FitResult
"""
