"""The box: axis-aligned, given by two diagonal corners (negative distance inside)."""
from __future__ import annotations

import torch

from .shape import PARAM_WIDTH, Shape, linear_image, safe_norm, segment_offset


def pack(corners: list[torch.Tensor], radius: float) -> torch.Tensor:
    """``(lo_x, lo_y, hi_x, hi_y, 0)``."""
    a, b = corners
    return torch.cat([torch.minimum(a, b), torch.maximum(a, b), a.new_zeros(*a.shape[:-1], PARAM_WIDTH - 4)], -1)


def _from_centre(qx, qy, params):
    """``q`` relative to the box's centre, and how far beyond its half-widths it lies along each axis."""
    lx, ly, hx, hy = params[:4]
    rx, ry = qx - (lx + hx) / 2, qy - (ly + hy) / 2
    return rx, ry, rx.abs() - (hx - lx) / 2, ry.abs() - (hy - ly) / 2


def local(qx, qy, params):
    _, _, dx, dy = _from_centre(qx, qy, params)
    outside = safe_norm(dx.clamp_min(0), dy.clamp_min(0))
    inside = torch.maximum(dx, dy).clamp_max(0)
    return outside + inside


def slope(qx, qy, params):
    """`local` and its gradient: outside, the unit vector from the nearest point; inside and on the edge, the
    outward normal of the nearest edge (at a corner or a tie, either edge's: both are subgradients)."""
    rx, ry, dx, dy = _from_centre(qx, qy, params)
    ox, oy = dx.clamp_min(0), dy.clamp_min(0)
    outside = safe_norm(ox, oy)
    inside = torch.maximum(dx, dy).clamp_max(0)
    sx, sy = torch.sign(rx), torch.sign(ry)
    within = (ox == 0) & (oy == 0)
    across = dx >= dy  # the nearest edge is a vertical one
    gx = torch.where(within, torch.where(across, sx, 0), sx * ox / outside)
    gy = torch.where(within, torch.where(across, 0, sy), sy * oy / outside)
    return outside + inside, gx, gy, torch.where(within, torch.inf, outside)


def _image_edges(x, y, forward, params):
    """The parallelogram ``T(box)``: each image edge's offset to ``x`` (stacked ``(4, ...)`` x and y) and whether
    ``x`` is inside."""
    image, tx, ty = linear_image(forward)
    lx, ly, hx, hy = params[:4]
    ox, oy = image(lx, ly)
    wx, wy = x - ox - tx, y - oy - ty             # x relative to the image of the lower-left corner
    ex, ey = image(hx - lx, torch.zeros_like(hx))   # the image of the box's horizontal side
    fx, fy = image(torch.zeros_like(hy), hy - ly)   # and of its vertical side
    offsets = [
        segment_offset(wx, wy, ex, ey),                   # bottom: from lower-left along e
        segment_offset(wx - fx, wy - fy, ex, ey),         # top: from upper-left along e
        segment_offset(wx, wy, fx, fy),                   # left: from lower-left along f
        segment_offset(wx - ex, wy - ey, fx, fy),         # right: from lower-right along f
    ]
    # inside when w = u e + v f with 0 < u, v < 1 (Cramer's rule, without dividing by det [e, f])
    det = ex * fy - ey * fx
    u_det, v_det = wx * fy - wy * fx, ex * wy - ey * wx
    inside = (u_det * det > 0) & (v_det * det > 0) & (u_det.abs() < det.abs()) & (v_det.abs() < det.abs())
    return torch.stack([o[0] for o in offsets]), torch.stack([o[1] for o in offsets]), inside


def affine(x, y, qx, qy, forward, smallest, params):
    """The exact signed distance to the parallelogram ``T(box)``: the distance to the nearest of its four image
    edges, negative inside."""
    vx, vy, inside = _image_edges(x, y, forward, params)
    edges = safe_norm(vx, vy).amin(0)
    return torch.where(inside, -edges, edges)


def affine_slope(x, y, qx, qy, inverse, forward, smallest, params):
    """`affine` and its gradient in the plane: the unit vector from the nearest edge's nearest point, turned
    outward inside (at a tie, either edge's: both are subgradients)."""
    vx, vy, inside = _image_edges(x, y, forward, params)
    edges, nearest = safe_norm(vx, vy).min(0)
    sign = torch.where(inside, -1.0, 1.0).to(edges.dtype) / edges
    gx = vx.gather(0, nearest[None])[0] * sign
    gy = vy.gather(0, nearest[None])[0] * sign
    return torch.where(inside, -edges, edges), gx, gy, edges


SHAPE = Shape("box", points=2, radius="unused", pack=pack, local=local, affine=affine, slope=slope,
              affine_slope=affine_slope)
