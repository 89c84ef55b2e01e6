"""Primitives: the shapes a fractal is drawn with, defined on control points so that they move with them.

A primitive's kind is an entry of the table `ifslib.core.geometry.shapes.SHAPES` (one module a kind: ``segment``,
a capsule of optional thickness; ``box``, axis-aligned by two diagonal corners; ``disk``, a centre and a radius),
which carries its number of points, its radius, its packing into `PARAM_WIDTH` numbers and its distances.
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
