"""Primitives: the shapes a fractal is drawn with, defined on control points so that they move with them; each
kind an entry of the table `ifslib.core.geometry.shapes.SHAPES`."""
from __future__ import annotations

from dataclasses import dataclass

import torch

from ...errors import IFSError
from .shapes import PARAM_WIDTH, SHAPES

PRIMITIVE_KINDS = tuple(SHAPES)


@dataclass(frozen=True)
class Primitive:
    """A shape on control points: a ``kind`` of `PRIMITIVE_KINDS`, its ``points`` (two indices for a segment or a
    box's diagonal, one for a disk's centre) and its ``radius`` (a segment's thickness, a disk's radius)."""

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
    """Each primitive's geometry packed into `PARAM_WIDTH` numbers, ``(p, PARAM_WIDTH)`` (``(B, p, ...)`` for a batch
    of points), differentiable in ``points``."""
    rows = [SHAPES[prim.kind].pack([points[..., i, :] for i in prim.points], prim.radius) for prim in primitives]
    return torch.stack(rows, -2)
