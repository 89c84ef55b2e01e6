"""Named IFSs for the paper's cases: the Koch curve, the Sierpinski carpet and n x n grids.

Each function returns a fresh `IFS` centred in the image plane ``[-0.5, 0.5]^2``.
"""
from __future__ import annotations

import math

import numpy as np

from .errors import IFSError
from .ifs import IFS


def koch(depth: int = 3, width: float = 0.8, radius: float = 0.0) -> IFS:
    """The Koch curve from five control points, as the paper builds it.

    Points ``p0 .. p4`` lie on the base segment from ``(-width/2, 0)`` to ``(width/2, 0)`` with the
    peak ``p2`` at height ``width * sqrt(3) / 6``; rule ``i`` maps the segment ``p0 -> p4`` onto
    ``p_i -> p_{i+1}``. The primitive is the segment ``p0 -> p4`` (a capsule when ``radius`` > 0).

    With ``width = 1`` and the curve shifted to start at the origin these maps are the paper's
    Eq. (1), except that its printed ``T3`` translation ``(1/3, 0)`` must be ``(1/2, sqrt(3)/6)``.
    """
    w = float(width)
    points = [[-w / 2, 0.0], [-w / 6, 0.0], [0.0, w * math.sqrt(3) / 6], [w / 6, 0.0], [w / 2, 0.0]]
    rules = [{"kind": "segment", "from": [0, 4], "to": [i, i + 1]} for i in range(4)]
    return IFS(points, rules, [{"kind": "segment", "points": [0, 4], "radius": radius}], depth=depth, name="koch")


def grid(n: int, depth: int = 3, extent: float = 0.8, skip: tuple[tuple[int, int], ...] = ()) -> IFS:
    """The square split into ``n x n`` sub-squares, each a scaled copy of the whole.

    Control points are the ``(n + 1)^2`` grid corners (row-major from the lower left); rule
    ``(i, j)`` maps the outer square's diagonal onto sub-square ``(i, j)``'s. The primitive is the
    outer box. ``skip`` lists ``(i, j)`` sub-squares (column i, row j from the lower left) without
    a rule. This is what the paper's repository used for the apple.
    """
    if isinstance(n, bool) or not isinstance(n, int) or n < 2:
        raise IFSError(f"grid(n) needs an integer n >= 2, got {n!r}")
    ticks = np.linspace(-extent / 2, extent / 2, n + 1)
    points = [[float(x), float(y)] for y in ticks for x in ticks]

    def corner(i: int, j: int) -> int:
        return j * (n + 1) + i

    outer = [corner(0, 0), corner(n, n)]
    rules = [{"kind": "square", "from": outer, "to": [corner(i, j), corner(i + 1, j + 1)]}
             for j in range(n) for i in range(n) if (i, j) not in set(skip)]
    return IFS(points, rules, [{"kind": "box", "points": outer}], depth=depth, name=f"grid{n}")


def sierpinski_carpet(depth: int = 3, extent: float = 0.8) -> IFS:
    """The Sierpinski carpet: a 3 x 3 grid without its centre square (8 square rules)."""
    ifs = grid(3, depth=depth, extent=extent, skip=((1, 1),))
    ifs.name = "sierpinski_carpet"
    return ifs


PATTERNS = {"koch": koch, "sierpinski_carpet": sierpinski_carpet, "carpet": sierpinski_carpet}


def by_name(name: str, depth: int = 3) -> IFS:
    """A pattern by name: ``koch``, ``carpet`` / ``sierpinski_carpet``, or ``gridN`` (e.g. ``grid3``)."""
    if name in PATTERNS:
        return PATTERNS[name](depth=depth)
    if name.startswith("grid") and name[4:].isdigit():
        return grid(int(name[4:]), depth=depth)
    raise IFSError(f"unknown pattern {name!r}; known: koch, carpet, sierpinski_carpet, gridN (e.g. grid3)")
