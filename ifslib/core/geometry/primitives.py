"""Primitives: the shapes a fractal is drawn with, each with an exact signed distance.

A primitive is defined on control points (so it moves with them); its kind is an entry of the table
`ifslib.core.geometry.shapes.SHAPES` (one module a kind), which carries what the code needs of it: its
number of points, whether it takes a radius, its packing into `PARAM_WIDTH` numbers, and its distances:

``segment``
    Two point indices and an optional thickness ``radius`` (a capsule; radius 0 is the bare segment).
``box``
    Axis-aligned box given by two diagonal corner indices (negative distance inside).
``disk``
    One centre index and a ``radius`` > 0.

Every distance is exact and therefore 1-Lipschitz; the nearest-leaf search relies on that.

`local_sdf` is a primitive's distance in its own frame; a similarity of scale ``s`` turns it into
the distance to the moved shape by ``s * d(T^-1 x)``. Under a general affine map that law fails
(a shear stretches some directions more than others), so `affine_sdf` measures in the plane
instead: a segment's image is a segment and a box's image a parallelogram, and their distances
are computed exactly there; a disk's image is an ellipse, whose exact distance has no closed form,
so it gets a 1-Lipschitz lower bound with the exact ellipse as its zero set.
"""
from __future__ import annotations

from dataclasses import dataclass

import torch

from ...errors import IFSError
from .shapes import PARAM_WIDTH, SHAPES

PRIMITIVE_KINDS = tuple(SHAPES)


@dataclass(frozen=True)
class Primitive:
    """A shape on control points.

    Parameters
    ----------
    kind : str
        One of `PRIMITIVE_KINDS` (``"segment"``, ``"box"``, ``"disk"``).
    points : tuple of int
        Two indices (segment endpoints, box diagonal corners) or one (disk centre).
    radius : float
        Capsule thickness for a segment (>= 0), radius for a disk (> 0); unused for a box.
    """

    kind: str
    points: tuple[int, ...]
    radius: float = 0.0

    def __post_init__(self) -> None:
        if self.kind not in PRIMITIVE_KINDS:
            raise IFSError(f"unknown primitive kind {self.kind!r}; known kinds: {', '.join(PRIMITIVE_KINDS)}")
        pts = tuple(self.points)
        need = SHAPES[self.kind].points
        if len(pts) != need or not all(isinstance(i, int) and not isinstance(i, bool) for i in pts):
            raise IFSError(f"a {self.kind} primitive needs {need} point index(es) in 'points', got {pts!r}")
        object.__setattr__(self, "points", pts)
        radius = float(self.radius)
        if not radius == radius or radius < 0 or radius == float("inf"):
            raise IFSError(f"a {self.kind} primitive's radius must be a finite number >= 0, got {self.radius!r}")
        if SHAPES[self.kind].radius == "required" and radius <= 0:
            raise IFSError(f"a disk primitive needs a radius > 0, got {self.radius!r}")
        object.__setattr__(self, "radius", radius)


def primitive_params(points: torch.Tensor, primitives: list[Primitive]) -> torch.Tensor:
    """Pack each primitive's geometry into `PARAM_WIDTH` numbers (5), differentiable in ``points``.

    Parameters
    ----------
    points : torch.Tensor
        Control points, ``(n, 2)``, or a batch ``(B, n, 2)``.
    primitives : list of Primitive
        The ``p`` primitives.

    Returns
    -------
    torch.Tensor
        ``(p, PARAM_WIDTH)`` (``(B, p, PARAM_WIDTH)`` for a batch): segment ``(ax, ay, bx, by, radius)``; box ``(lo_x, lo_y, hi_x, hi_y, 0)``;
        disk ``(cx, cy, radius, 0, 0)``.
    """
    rows = [SHAPES[prim.kind].pack([points[..., i, :] for i in prim.points], prim.radius) for prim in primitives]
    return torch.stack(rows, -2)


def local_sdf(kind: str, qx: torch.Tensor, qy: torch.Tensor, params: torch.Tensor) -> torch.Tensor:
    """Signed distance from points ``(qx, qy)`` to a primitive, in the primitive's own frame.

    Parameters
    ----------
    kind : str
        Primitive kind.
    qx, qy : torch.Tensor
        Query coordinates, any broadcastable shape ``S``.
    params : torch.Tensor
        ``(..., PARAM_WIDTH)`` packed geometry (see `primitive_params`), its leading shape broadcastable to ``S``.

    Returns
    -------
    torch.Tensor
        Signed distances, shape ``S`` (broadcast).
    """
    return _shape(kind).local(qx, qy, params.unbind(-1))


def affine_sdf(kind: str, x: torch.Tensor, y: torch.Tensor, qx: torch.Tensor, qy: torch.Tensor, forward: torch.Tensor,
               smallest: torch.Tensor, params: torch.Tensor) -> torch.Tensor:
    """Signed distance in the plane from ``x`` to ``T(D)``, for an affine map ``T x = A q + t``.

    Parameters
    ----------
    kind : str
        Primitive kind.
    x, y : torch.Tensor
        Query points in the plane, any shape ``S``.
    qx, qy : torch.Tensor
        The same points pulled back into the primitive's frame, ``q = T^-1 x`` (shape ``S``); only
        the disk uses them.
    forward : torch.Tensor
        ``(..., 6)``: ``T`` as ``(a, b, tx, c, d, ty)``, i.e. ``A = [[a, b], [c, d]]``, ``t = (tx, ty)``.
    smallest : torch.Tensor
        ``(...)``: ``A``'s smallest singular value.
    params : torch.Tensor
        ``(..., PARAM_WIDTH)`` packed primitive geometry (see `primitive_params`).

    Returns
    -------
    torch.Tensor
        Shape ``S``. What it is, by kind:

        * ``segment``: the exact distance to the image segment ``[T a, T b]``, less
          ``smallest * radius``. A thick segment under a shear is drawn as the capsule of radius
          ``smallest * radius`` around its image segment (for a similarity, exactly its image).
        * ``box``: the exact signed distance to the parallelogram ``T(box)``: the distance to the
          nearest of its four image edges, negative inside.
        * ``disk``: ``smallest * d_disk(q)``, a lower bound of the distance to the ellipse
          ``T(disk)`` (exact for a similarity) with the ellipse itself as its zero set. It is
          1-Lipschitz, because ``T^-1`` stretches distances by at most ``1 / smallest``, which is
          what the nearest-leaf search needs.

    Notes
    -----
    Segments and boxes are measured from the forward map alone, in the plane: a deep word of
    nearly flat maps has an inverse with entries in the millions, and pulling ``x`` back through it
    and pushing the difference forward again would lose every digit in float32.
    """
    return _shape(kind).affine(x, y, qx, qy, forward, smallest, params.unbind(-1))


def _shape(kind: str):
    if kind not in SHAPES:
        raise IFSError(f"unknown primitive kind {kind!r}")
    return SHAPES[kind]
