"""Primitives: the shapes a fractal is drawn with, each with an exact signed distance.

A primitive is defined on control points (so it moves with them) and has three kinds:

``segment``
    Two point indices and an optional thickness ``radius`` (a capsule; radius 0 is the bare segment).
``box``
    Axis-aligned box given by two diagonal corner indices (negative distance inside).
``disk``
    One centre index and a ``radius`` > 0.

Every distance here is exact and therefore 1-Lipschitz; the nearest-leaf search relies on that.
Square roots go through `_safe_norm`, whose gradient is 0 (not NaN) where the distance is 0.

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

PRIMITIVE_KINDS = ("segment", "box", "disk")
_N_POINTS = {"segment": 2, "box": 2, "disk": 1}


@dataclass(frozen=True)
class Primitive:
    """A shape on control points.

    Parameters
    ----------
    kind : {"segment", "box", "disk"}
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
        need = _N_POINTS[self.kind]
        if len(pts) != need or not all(isinstance(i, int) and not isinstance(i, bool) for i in pts):
            raise IFSError(f"a {self.kind} primitive needs {need} point index(es) in 'points', got {pts!r}")
        object.__setattr__(self, "points", pts)
        radius = float(self.radius)
        if not radius == radius or radius < 0 or radius == float("inf"):
            raise IFSError(f"a {self.kind} primitive's radius must be a finite number >= 0, got {self.radius!r}")
        if self.kind == "disk" and radius <= 0:
            raise IFSError(f"a disk primitive needs a radius > 0, got {self.radius!r}")
        object.__setattr__(self, "radius", radius)


def primitive_params(points: torch.Tensor, primitives: list[Primitive]) -> torch.Tensor:
    """Pack each primitive's geometry into 5 numbers, differentiable in ``points``.

    Parameters
    ----------
    points : torch.Tensor
        Control points, ``(n, 2)``, or a batch ``(B, n, 2)``.
    primitives : list of Primitive
        The ``p`` primitives.

    Returns
    -------
    torch.Tensor
        ``(p, 5)`` (``(B, p, 5)`` for a batch): segment ``(ax, ay, bx, by, radius)``; box ``(lo_x, lo_y, hi_x, hi_y, 0)``;
        disk ``(cx, cy, radius, 0, 0)``.
    """
    rows = []
    for prim in primitives:
        if prim.kind == "segment":
            a, b = points[..., prim.points[0], :], points[..., prim.points[1], :]
            rows.append(torch.cat([a, b, a.new_tensor([prim.radius]).expand(*a.shape[:-1], 1)], -1))
        elif prim.kind == "box":
            a, b = points[..., prim.points[0], :], points[..., prim.points[1], :]
            rows.append(torch.cat([torch.minimum(a, b), torch.maximum(a, b), a.new_zeros(*a.shape[:-1], 1)], -1))
        else:
            c = points[..., prim.points[0], :]
            rows.append(torch.cat([c, c.new_tensor([prim.radius, 0.0, 0.0]).expand(*c.shape[:-1], 3)], -1))
    return torch.stack(rows, -2)


def _safe_norm(x: torch.Tensor, y: torch.Tensor) -> torch.Tensor:
    # clamp_min makes the gradient 0 at an exact zero instead of sqrt's NaN.
    return (x * x + y * y).clamp_min(torch.finfo(x.dtype).tiny).sqrt()


def _segment_distance(wx, wy, ux, uy):
    """Distance from the origin-relative point ``w`` to the segment from 0 to ``u`` (any shapes)."""
    h = ((wx * ux + wy * uy) / (ux * ux + uy * uy).clamp_min(torch.finfo(wx.dtype).tiny)).clamp(0, 1)
    return _safe_norm(wx - h * ux, wy - h * uy)


def local_sdf(kind: str, qx: torch.Tensor, qy: torch.Tensor, params: torch.Tensor) -> torch.Tensor:
    """Signed distance from points ``(qx, qy)`` to a primitive, in the primitive's own frame.

    Parameters
    ----------
    kind : str
        Primitive kind.
    qx, qy : torch.Tensor
        Query coordinates, any broadcastable shape ``S``.
    params : torch.Tensor
        ``(..., 5)`` packed geometry (see `primitive_params`), its leading shape broadcastable to ``S``.

    Returns
    -------
    torch.Tensor
        Signed distances, shape ``S`` (broadcast).
    """
    p = params.unbind(-1)
    if kind == "segment":
        ax, ay, bx, by, r = p
        return _segment_distance(qx - ax, qy - ay, bx - ax, by - ay) - r
    if kind == "box":
        lx, ly, hx, hy, _ = p
        cx, cy = (lx + hx) / 2, (ly + hy) / 2
        dx = (qx - cx).abs() - (hx - lx) / 2
        dy = (qy - cy).abs() - (hy - ly) / 2
        outside = _safe_norm(dx.clamp_min(0), dy.clamp_min(0))
        inside = torch.maximum(dx, dy).clamp_max(0)
        return outside + inside
    if kind == "disk":
        cx, cy, r, _, _ = p
        return _safe_norm(qx - cx, qy - cy) - r
    raise IFSError(f"unknown primitive kind {kind!r}")


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
        ``(..., 5)`` packed primitive geometry (see `primitive_params`).

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
    a, b, tx, c, d, ty = forward.unbind(-1)
    p = params.unbind(-1)

    def image(vx, vy):  # A v
        return a * vx + b * vy, c * vx + d * vy

    if kind == "segment":
        ax, ay, bx, by, r = p
        sx, sy = image(ax, ay)
        ux, uy = image(bx - ax, by - ay)
        return _segment_distance(x - sx - tx, y - sy - ty, ux, uy) - smallest * r
    if kind == "box":
        lx, ly, hx, hy, _ = p
        ox, oy = image(lx, ly)
        wx, wy = x - ox - tx, y - oy - ty             # x relative to the image of the lower-left corner
        ex, ey = image(hx - lx, torch.zeros_like(hx))   # the image of the box's horizontal side
        fx, fy = image(torch.zeros_like(hy), hy - ly)   # and of its vertical side
        edges = torch.stack([
            _segment_distance(wx, wy, ex, ey),                   # bottom: from lower-left along e
            _segment_distance(wx - fx, wy - fy, ex, ey),         # top: from upper-left along e
            _segment_distance(wx, wy, fx, fy),                   # left: from lower-left along f
            _segment_distance(wx - ex, wy - ey, fx, fy),         # right: from lower-right along f
        ]).amin(0)
        # inside when w = u e + v f with 0 < u, v < 1 (Cramer's rule, without dividing by det [e, f])
        det = ex * fy - ey * fx
        u_det, v_det = wx * fy - wy * fx, ex * wy - ey * wx
        inside = (u_det * det > 0) & (v_det * det > 0) & (u_det.abs() < det.abs()) & (v_det.abs() < det.abs())
        return torch.where(inside, -edges, edges)
    if kind == "disk":
        return smallest * local_sdf(kind, qx, qy, params)
    raise IFSError(f"unknown primitive kind {kind!r}")
