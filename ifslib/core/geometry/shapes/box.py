"""The box: axis-aligned, given by two diagonal corners (negative distance inside)."""
from __future__ import annotations

import torch

from .shape import PARAM_WIDTH, Shape, linear_image, safe_norm, segment_distance


def pack(corners: list[torch.Tensor], radius: float) -> torch.Tensor:
    """``(lo_x, lo_y, hi_x, hi_y, 0)``."""
    a, b = corners
    return torch.cat([torch.minimum(a, b), torch.maximum(a, b), a.new_zeros(*a.shape[:-1], PARAM_WIDTH - 4)], -1)


def local(qx, qy, params):
    lx, ly, hx, hy = params[:4]
    cx, cy = (lx + hx) / 2, (ly + hy) / 2
    dx = (qx - cx).abs() - (hx - lx) / 2
    dy = (qy - cy).abs() - (hy - ly) / 2
    outside = safe_norm(dx.clamp_min(0), dy.clamp_min(0))
    inside = torch.maximum(dx, dy).clamp_max(0)
    return outside + inside


def slope(qx, qy, params):
    """`local` and its gradient: outside, the unit vector from the nearest point; inside and on the edge, the
    outward normal of the nearest edge (at a corner or a tie, either edge's: both are subgradients)."""
    lx, ly, hx, hy = params[:4]
    cx, cy = (lx + hx) / 2, (ly + hy) / 2
    dx = (qx - cx).abs() - (hx - lx) / 2
    dy = (qy - cy).abs() - (hy - ly) / 2
    ox, oy = dx.clamp_min(0), dy.clamp_min(0)
    outside = safe_norm(ox, oy)
    inside = torch.maximum(dx, dy).clamp_max(0)
    sx, sy = torch.sign(qx - cx), torch.sign(qy - cy)
    within = (ox == 0) & (oy == 0)
    across = dx >= dy  # the nearest edge is a vertical one
    gx = torch.where(within, torch.where(across, sx, 0), sx * ox / outside)
    gy = torch.where(within, torch.where(across, 0, sy), sy * oy / outside)
    return outside + inside, gx, gy, torch.where(within, torch.inf, outside)


def affine(x, y, qx, qy, forward, smallest, params):
    """The exact signed distance to the parallelogram ``T(box)``: the distance to the nearest of its four image
    edges, negative inside."""
    image, tx, ty = linear_image(forward)
    lx, ly, hx, hy = params[:4]
    ox, oy = image(lx, ly)
    wx, wy = x - ox - tx, y - oy - ty             # x relative to the image of the lower-left corner
    ex, ey = image(hx - lx, torch.zeros_like(hx))   # the image of the box's horizontal side
    fx, fy = image(torch.zeros_like(hy), hy - ly)   # and of its vertical side
    edges = torch.stack([
        segment_distance(wx, wy, ex, ey),                   # bottom: from lower-left along e
        segment_distance(wx - fx, wy - fy, ex, ey),         # top: from upper-left along e
        segment_distance(wx, wy, fx, fy),                   # left: from lower-left along f
        segment_distance(wx - ex, wy - ey, fx, fy),         # right: from lower-right along f
    ]).amin(0)
    # inside when w = u e + v f with 0 < u, v < 1 (Cramer's rule, without dividing by det [e, f])
    det = ex * fy - ey * fx
    u_det, v_det = wx * fy - wy * fx, ex * wy - ey * wx
    inside = (u_det * det > 0) & (v_det * det > 0) & (u_det.abs() < det.abs()) & (v_det.abs() < det.abs())
    return torch.where(inside, -edges, edges)


SHAPE = Shape("box", points=2, radius="unused", pack=pack, local=local, affine=affine, slope=slope)
