"""The disk: one centre and a ``radius`` > 0."""
from __future__ import annotations

import torch

from .shape import PARAM_WIDTH, Shape, norm_slope, safe_norm


def pack(corners: list[torch.Tensor], radius: float) -> torch.Tensor:
    """``(cx, cy, radius, 0, 0)``."""
    (c,) = corners
    return torch.cat([c, c.new_tensor([radius] + [0.0] * (PARAM_WIDTH - 3)).expand(*c.shape[:-1], PARAM_WIDTH - 2)], -1)


def local(qx, qy, params):
    cx, cy, r = params[:3]
    return safe_norm(qx - cx, qy - cy) - r


def slope(qx, qy, params):
    """`local` and its gradient: the unit vector from the centre (0 at the centre)."""
    cx, cy, r = params[:3]
    return norm_slope(qx - cx, qy - cy, r)


def affine(x, y, qx, qy, forward, smallest, params):
    """``smallest * d_disk(q)``: a lower bound of the distance to the ellipse ``T(disk)`` (exact for a similarity),
    with the ellipse itself as its zero set. It is 1-Lipschitz, because ``T^-1`` stretches distances by at most
    ``1 / smallest``, which is what the nearest-leaf search needs."""
    return smallest * local(qx, qy, params)


def affine_slope(x, y, qx, qy, inverse, forward, smallest, params):
    """`affine` and its gradient in the plane, ``smallest M^T`` times the disk's own for the inverse's linear part ``M``."""
    d, gx, gy, reach = slope(qx, qy, params)
    m0, m1, _, m3, m4, _ = inverse.unbind(-1)
    return smallest * d, smallest * (m0 * gx + m3 * gy), smallest * (m1 * gx + m4 * gy), smallest * reach


SHAPE = Shape("disk", points=1, radius="required", pack=pack, local=local, affine=affine, slope=slope,
              affine_slope=affine_slope)
