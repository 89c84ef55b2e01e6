"""`Shape`: what the code needs of a primitive's kind, and the distances the kinds share (exact, so 1-Lipschitz,
as the nearest-leaf search needs)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import torch

#: The numbers a primitive's geometry is packed into (`Shape.pack`); a kind with more widens it here.
PARAM_WIDTH = 5


@dataclass(frozen=True)
class Shape:
    """One kind of primitive: its name, control points, radius rule, packing into `PARAM_WIDTH` numbers, its signed
    distance in its own frame (``local``) and to its image under an affine map (``affine``: the similarity law
    fails under a shear), and optionally the same with gradients (``slope``, ``affine_slope``) for the search."""

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
