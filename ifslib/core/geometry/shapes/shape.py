"""`Shape`: what the code needs of a primitive's kind, and the distances the kinds share.

Every distance is exact and therefore 1-Lipschitz (the nearest-leaf search relies on that); square
roots go through `safe_norm`, whose gradient is 0 (not NaN) where the distance is 0.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import torch

#: The numbers a primitive's geometry is packed into (`Shape.pack`); a kind with more widens it here.
PARAM_WIDTH = 5


@dataclass(frozen=True)
class Shape:
    """One kind of primitive, as the table `ifslib.core.geometry.shapes.SHAPES` holds it.

    Attributes
    ----------
    kind : str
        Its name in the ``ifslib/1`` file (and in its JSON Schema's list of kinds).
    points : int
        How many control points it is defined on.
    radius : {"optional", "required", "unused"}
        Whether it takes a radius (a segment's thickness, a disk's radius); the file writes a required one always.
    pack : callable
        ``pack(corners, radius) -> (..., PARAM_WIDTH)``: its geometry from its ``points`` control points
        (each ``(..., 2)``), differentiable in them.
    local : callable
        ``local(qx, qy, params) -> distances``: the signed distance in its own frame (``params`` unbound,
        `PARAM_WIDTH` tensors broadcastable to the points').
    affine : callable
        ``affine(x, y, qx, qy, forward, smallest, params)``: the distance in the plane to its image under an
        affine map (see `ifslib.core.geometry.primitives.affine_sdf`).
    """

    kind: str
    points: int
    radius: str
    pack: Callable[[list[torch.Tensor], float], torch.Tensor]
    local: Callable[..., torch.Tensor]
    affine: Callable[..., torch.Tensor]


def safe_norm(x: torch.Tensor, y: torch.Tensor) -> torch.Tensor:
    """``sqrt(x² + y²)``, its gradient 0 at an exact zero instead of sqrt's NaN."""
    return (x * x + y * y).clamp_min(torch.finfo(x.dtype).tiny).sqrt()


def segment_distance(wx, wy, ux, uy):
    """Distance from the origin-relative point ``w`` to the segment from 0 to ``u`` (any shapes)."""
    h = ((wx * ux + wy * uy) / (ux * ux + uy * uy).clamp_min(torch.finfo(wx.dtype).tiny)).clamp(0, 1)
    return safe_norm(wx - h * ux, wy - h * uy)


def linear_image(forward: torch.Tensor):
    """``v -> A v`` for the affine maps ``forward`` ``(..., 6)`` = ``(a, b, tx, c, d, ty)``, and ``(tx, ty)``."""
    a, b, tx, c, d, ty = forward.unbind(-1)
    return (lambda vx, vy: (a * vx + b * vy, c * vx + d * vy)), tx, ty
