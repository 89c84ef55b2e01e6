"""The segment: two control points and an optional thickness ``radius`` (a capsule; 0 is the bare segment)."""
from __future__ import annotations

import torch

from .shape import PARAM_WIDTH, Shape, linear_image, norm_slope, segment_distance, segment_offset


def pack(corners: list[torch.Tensor], radius: float) -> torch.Tensor:
    """``(ax, ay, bx, by, radius, 0...)``."""
    a, b = corners
    rest = a.new_tensor([radius] + [0.0] * (PARAM_WIDTH - 5)).expand(*a.shape[:-1], PARAM_WIDTH - 4)
    return torch.cat([a, b, rest], -1)


def local(qx, qy, params):
    ax, ay, bx, by, r = params[:5]
    return segment_distance(qx - ax, qy - ay, bx - ax, by - ay) - r


def slope(qx, qy, params):
    """`local` and its gradient: the unit vector from the segment's nearest point (0 on the segment)."""
    ax, ay, bx, by, r = params[:5]
    return norm_slope(*segment_offset(qx - ax, qy - ay, bx - ax, by - ay), r)


def affine(x, y, qx, qy, forward, smallest, params):
    """The exact distance to the image segment ``[T a, T b]``, less ``smallest * radius``: a thick segment under
    a shear is drawn as the capsule of radius ``smallest * radius`` around its image (for a similarity, exactly
    its image)."""
    image, tx, ty = linear_image(forward)
    ax, ay, bx, by, r = params[:5]
    sx, sy = image(ax, ay)
    ux, uy = image(bx - ax, by - ay)
    return segment_distance(x - sx - tx, y - sy - ty, ux, uy) - smallest * r


def affine_slope(x, y, qx, qy, inverse, forward, smallest, params):
    """`affine` and its gradient in the plane: the unit vector from the image segment's nearest point."""
    image, tx, ty = linear_image(forward)
    ax, ay, bx, by, r = params[:5]
    sx, sy = image(ax, ay)
    ux, uy = image(bx - ax, by - ay)
    return norm_slope(*segment_offset(x - sx - tx, y - sy - ty, ux, uy), smallest * r)


SHAPE = Shape("segment", points=2, radius="optional", pack=pack, local=local, affine=affine, slope=slope,
              affine_slope=affine_slope)
