"""Named IFSs for the paper's cases, each a fresh `IFS` centred in the image plane ``[-0.5, 0.5]^2``."""
from __future__ import annotations

import math

import numpy as np
import torch

from ...errors import IFSError, check_int
from .ifs import IFS


def koch(depth: int = 3, width: float = 0.8, radius: float = 0.0) -> IFS:
    """The Koch curve from five control points, as the paper builds it (its Eq. (1) with ``width = 1``, except that the
    printed ``T3`` translation ``(1/3, 0)`` must be ``(1/2, sqrt(3)/6)``)."""
    w = float(width)
    points = [[-w / 2, 0.0], [-w / 6, 0.0], [0.0, w * math.sqrt(3) / 6], [w / 6, 0.0], [w / 2, 0.0]]
    return koch_like(points, depth=depth, radius=radius, name="koch")


def koch_unit(depth: int = 3) -> IFS:
    """The Koch curve in the frame of the paper's Eq. (1), from ``(0, 0)`` to ``(1, 0)``, float64: for its maps, not for drawing."""
    ifs = koch(depth=depth, width=1.0).to(torch.float64)
    ifs = ifs.clone(ifs.points.detach() + torch.tensor([0.5, 0.0], dtype=torch.float64))
    ifs.name = "koch_unit"
    return ifs


def grid(n: int, depth: int = 3, extent: float = 0.8, skip: tuple[tuple[int, int], ...] = ()) -> IFS:
    """The square split into ``n x n`` sub-squares, each a scaled copy of the whole; ``skip`` lists ``(i, j)``
    sub-squares without a rule. This is what the paper's repository used for the apple."""
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


def koch_paper(seed: int = 0, depth: int = 3, jitter: float = 0.1) -> IFS:
    """The paper's own Koch start (its repository's ``koch_setup.py``): five jittered points on ``x = 0.05``,
    the four Koch rules, and the four segments as primitives (radius 0.005)."""
    rng = np.random.default_rng(seed)
    points = np.stack([np.full(5, 0.05), np.linspace(0.4, -0.4, 5)], 1) + rng.uniform(-jitter, jitter, (5, 2))
    rules = [{"kind": "segment", "from": [0, 4], "to": [i, i + 1]} for i in range(4)]
    prims = [{"kind": "segment", "points": [i, i + 1], "radius": 0.005} for i in range(4)]
    return IFS(points.tolist(), rules, prims, depth=depth, name="koch_paper")


def rosette(n: int = 6, depth: int = 3, radius: float = 0.4, inner: float = 0.05, width: float = 0.03) -> IFS:
    """An ``n``-fold rosette: ``n`` rotated, scaled copies of the whole, one per petal (the base segment
    ``p0 -> p1`` mapped onto ``a_i -> b_i``); with ``n = 6`` the MPEG-7 flower's symmetry."""
    check_int(n, "n", 2)
    points = [[0.0, 0.0], [radius, 0.0]]
    for i in range(n):
        angle = 2 * math.pi * i / n
        c, s = math.cos(angle), math.sin(angle)
        points += [[inner * c, inner * s], [radius * c, radius * s]]
    rules = [{"kind": "segment", "from": [0, 1], "to": [2 + 2 * i, 3 + 2 * i]} for i in range(n)]
    return IFS(points, rules, [{"kind": "segment", "points": [0, 1], "radius": width}], depth=depth, name=f"rosette{n}")


def koch_like(points, depth: int = 3, radius: float = 0.0, name: str = "koch_like") -> IFS:
    """A self-similar curve from any polyline ``(n, 2)`` with the Koch curve's rules; every segment must be shorter
    than the base ``p0 -> p_(n-1)`` (else its rule would not contract)."""
    pts = np.asarray(points.detach().cpu() if isinstance(points, torch.Tensor) else points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] != 2 or pts.shape[0] < 3:
        raise IFSError(f"koch_like needs an (n, 2) polyline with n >= 3 points, got shape {pts.shape}")
    if not np.isfinite(pts).all():
        raise IFSError("koch_like: the polyline holds values that are not finite (NaN or inf)")
    base = float(np.linalg.norm(pts[-1] - pts[0]))
    if not base > 0:
        raise IFSError("koch_like: the polyline's first and last points coincide, so there is no base segment")
    for i, length in enumerate(np.linalg.norm(np.diff(pts, axis=0), axis=1).tolist()):
        if not 0 < length < base:
            raise IFSError(f"koch_like: segment {i} (p{i} -> p{i + 1}) has length {length:.4g}, which must lie "
                           f"strictly between 0 and the base length {base:.4g} for its rule to be a contraction")
    n = len(pts)
    rules = [{"kind": "segment", "from": [0, n - 1], "to": [i, i + 1]} for i in range(n - 1)]
    return IFS(pts.tolist(), rules, [{"kind": "segment", "points": [0, n - 1], "radius": radius}], depth=depth, name=name)


#: The frame of an `affine` pattern: its source triangle is three corners of this square.
AFFINE_FRAME = ((-0.5, -0.5), (0.5, -0.5), (-0.5, 0.5), (0.5, 0.5))


def affine(maps, depth: int = 3, primitive: str = "box", name: str = "affine", extent: float = 1.0,
           dtype: torch.dtype = torch.float32) -> IFS:
    """An IFS of general affine maps ``(m, 2, 3)``, each an ``affine`` rule: the images of the fixed source square's
    corners are control points, so its six parameters train like any."""
    m = torch.as_tensor(maps, dtype=torch.float64)
    if m.ndim != 3 or m.shape[1] not in (2, 3) or m.shape[2] != 3 or m.shape[0] == 0:
        raise IFSError(f"maps must have shape (m, 2, 3) or (m, 3, 3) with m >= 1, got {tuple(m.shape)}")
    if primitive not in ("box", "segment"):
        raise IFSError(f"an affine pattern draws a 'box' or a 'segment', got {primitive!r}")
    frame = torch.tensor(AFFINE_FRAME, dtype=torch.float64) * float(extent)
    images = frame[:3] @ m[:, :2, :2].transpose(1, 2) + m[:, None, :2, 2]   # (m, 3, 2)
    points = torch.cat([frame, images.reshape(-1, 2)]).tolist()
    rules = [{"kind": "affine", "from": [0, 1, 2], "to": [4 + 3 * i, 5 + 3 * i, 6 + 3 * i]} for i in range(m.shape[0])]
    prim = {"kind": "box", "points": [0, 3]} if primitive == "box" else {"kind": "segment", "points": [0, 1]}
    return IFS(points, rules, [prim], depth=depth, name=name, fixed=(0, 1, 2, 3), dtype=dtype)


#: Barnsley's fern in its classic coordinates (x in [-2.2, 2.7], y in [0, 10]): ``[A | t]`` per map.
#: The stem's first column is 0.001, not 0, so that a drawing at depth K (which inverts every map) works.
FERN_MAPS = (((0.001, 0.0, 0.0), (0.0, 0.16, 0.0)),
             ((0.85, 0.04, 0.0), (-0.04, 0.85, 1.6)),
             ((0.2, -0.26, 0.0), (0.23, 0.22, 1.6)),
             ((-0.15, 0.28, 0.0), (0.26, 0.24, 0.44)))


def fern(depth: int = 3, maps=FERN_MAPS, name: str = "fern") -> IFS:
    """Barnsley's fern scaled into the frame ``[-0.45, 0.45]^2``: four affine maps, the stem nearly singular.
    A drawing at a finite depth is not the fern: draw it with ``depth="attractor"``."""
    k = 0.09
    return affine(conjugated(np.asarray(maps, dtype=np.float64), k, -k * np.array([0.25, 5.0])), depth=depth,
                  name=name)


def sierpinski_triangle(depth: int = 3, extent: float = 0.8, name: str = "sierpinski_triangle") -> IFS:
    """The Sierpinski triangle: three `affine` maps of scale 1/2 towards the corners of a triangle of side ``extent``."""
    h = extent * math.sqrt(3) / 2
    corners = [(-extent / 2, -h / 2), (extent / 2, -h / 2), (0.0, h / 2)]
    maps = [[[0.5, 0.0, cx / 2], [0.0, 0.5, cy / 2]] for cx, cy in corners]
    return affine(maps, depth=depth, name=name)


def conjugated(maps: np.ndarray, k: float, b: np.ndarray) -> np.ndarray:
    """``(m, 2, 3)`` maps ``S w S^-1`` for the similarity ``S(x) = k x + b``: the maps whose attractor is ``S`` of
    theirs (the same linear parts, the shifts ``k t + b - L b``)."""
    linear = maps[:, :, :2]
    return np.concatenate([linear, (k * maps[:, :, 2] + b - linear @ b)[:, :, None]], 2)


PATTERNS = {"koch": koch, "sierpinski_triangle": sierpinski_triangle, "triangle": sierpinski_triangle, "sierpinski_carpet": sierpinski_carpet, "carpet": sierpinski_carpet, "koch_paper": koch_paper,
            "fern": fern}


def by_name(name: str, depth: int = 3) -> IFS:
    """A pattern by name: a key of `PATTERNS`, ``gridN`` or ``rosetteN``."""
    if name in PATTERNS:
        return PATTERNS[name](depth=depth)
    for prefix, build in (("grid", grid), ("rosette", rosette)):
        if name.startswith(prefix) and name[len(prefix):].isdigit():
            return build(int(name[len(prefix):]), depth=depth)
    raise IFSError(f"unknown pattern {name!r}; known: koch, koch_paper, carpet, sierpinski_carpet, fern, triangle, "
                   "gridN (e.g. grid3), rosetteN (e.g. rosette6)")
