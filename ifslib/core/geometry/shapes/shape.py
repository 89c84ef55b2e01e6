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
        ``affine(x, y, qx, qy, forward, smallest, params)``: the distance in the plane from ``(x, y)`` to its image
        under the affine map ``forward`` (``(..., 6)``: ``(a, b, tx, c, d, ty)``), whose smallest singular value
        is ``smallest``, ``(qx, qy)`` being the points pulled back. The similarity law ``s d(T^-1 x)`` fails
        under a shear, so a segment's and a box's images (a segment, a parallelogram) are measured exactly in the
        plane from the forward map alone (an inverse of nearly flat maps would lose every digit in float32), a
        thick segment as the capsule of radius ``smallest * radius``; a disk's image, an ellipse, gets
        ``smallest * d(q)``, a 1-Lipschitz lower bound with the ellipse as its zero set.
    slope : callable, optional
        ``slope(qx, qy, params) -> (distance, gx, gy, reach)``: `local`'s value, bit for bit, its gradient in
        the primitive's frame (a subgradient where it has a kink: 0 on a bare segment), and the length of the
        vector that gradient is the direction of (inf where the direction is exact): rounding moves that
        vector by a few ulps, so the direction is only as good as ``ulps / reach``. The nearest-leaf search
        uses it for a tighter bound (`ifslib.core.raster.nearest`); None where a kind has none.
    affine_slope : callable, optional
        ``affine_slope(x, y, qx, qy, inverse, forward, smallest, params) -> (distance, gx, gy, reach)``: `affine`'s
        value, bit for bit, its gradient in the plane, and the reach (as ``slope``'s, in plane units);
        ``inverse`` is ``(..., 6)``, the map's inverse. None where a kind has none.
    """

    kind: str
    points: int
    radius: str
    pack: Callable[[list[torch.Tensor], float], torch.Tensor]
    local: Callable[..., torch.Tensor]
    affine: Callable[..., torch.Tensor]
    slope: Callable[..., tuple[torch.Tensor, ...]] | None = None
    affine_slope: Callable[..., tuple[torch.Tensor, ...]] | None = None


def safe_norm(x: torch.Tensor, y: torch.Tensor) -> torch.Tensor:
    """``sqrt(x² + y²)``, its gradient 0 at an exact zero instead of sqrt's NaN."""
    return (x * x + y * y).clamp_min(torch.finfo(x.dtype).tiny).sqrt()


def segment_offset(wx, wy, ux, uy):
    """The vector from the nearest point of the segment from 0 to ``u`` to the origin-relative point ``w``."""
    h = ((wx * ux + wy * uy) / (ux * ux + uy * uy).clamp_min(torch.finfo(wx.dtype).tiny)).clamp(0, 1)
    return wx - h * ux, wy - h * uy


def segment_distance(wx, wy, ux, uy):
    """Distance from the origin-relative point ``w`` to the segment from 0 to ``u`` (any shapes)."""
    return safe_norm(*segment_offset(wx, wy, ux, uy))


def norm_slope(vx, vy, less):
    """``|v| - less`` (as `safe_norm` computes it), its gradient in ``v``, the unit vector ``v / |v|`` (0 at
    ``v = 0``), and ``|v|``: a `Shape.slope` for a distance measured from a point or a segment."""
    n = safe_norm(vx, vy)  # never 0: safe_norm's floor makes v / |v| = 0 at v = 0
    return n - less, vx / n, vy / n, n


def linear_image(forward: torch.Tensor):
    """``v -> A v`` for the affine maps ``forward`` ``(..., 6)`` = ``(a, b, tx, c, d, ty)``, and ``(tx, ty)``."""
    a, b, tx, c, d, ty = forward.unbind(-1)
    return (lambda vx, vy: (a * vx + b * vy, c * vx + d * vy)), tx, ty
