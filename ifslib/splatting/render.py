"""The differentiable chaos game: chains' points of an IFS splatted onto the pixel grid, an image of its invariant
measure with gradients to the maps and the probabilities.

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

from dataclasses import dataclass

import torch

from ..errors import IFSError, check_int
from ..core.geometry.attractor import check_contractive_maps
from ..core.geometry.leaves import check_bytes
from ..core.raster.chaos import CHAINS
from .chains import chain_points, replay
from .config import BYTES_PER_CORNER, BYTES_PER_POINT, BYTES_PER_POINT_STEP, GRADIENT_DEPTH, POINTS


@dataclass(frozen=True)
class SplatOptions:
    """How `splat_measure` draws.

    Attributes
    ----------
    points : int
        Points splatted, >= 1 (rounded up to whole steps of the `CHAINS` chains): the gray levels' noise falls
        like ``1 / sqrt(points per pixel)``.
    depth : int
        Last steps of each chain the gradient runs through (`GRADIENT_DEPTH`), >= 1.
    supersample : int
        Fine cells per pixel along each side, >= 1: each point's bilinear splat is this many times narrower.
    seed : int
        Seeds the chains (`chaos_game`): the same seed, the same points and image at any thread count.
    """

    points: int = POINTS
    depth: int = GRADIENT_DEPTH
    supersample: int = 1
    seed: int = 0

    def __post_init__(self) -> None:
        check_int(self.points, "points", 1)
        check_int(self.depth, "depth", 1, maximum=256)
        check_int(self.supersample, "supersample", 1, maximum=16)
        check_int(self.seed, "seed", 0)


def check_maps(maps: torch.Tensor, probabilities: torch.Tensor) -> None:
    """`IFSError` unless ``maps`` is ``(m, 3, 3)`` or ``(m, 2, 3)``, finite and contractive, and ``probabilities`` is
    ``(m,)``, finite, > 0 and sums to 1 (within 1e-5, float32's rounding)."""
    if not isinstance(maps, torch.Tensor) or maps.ndim != 3 or maps.shape[1:] not in ((3, 3), (2, 3)) \
            or maps.shape[0] < 1:
        raise IFSError(f"maps must be a tensor of shape (m, 3, 3) or (m, 2, 3), got "
                       f"{tuple(maps.shape) if isinstance(maps, torch.Tensor) else type(maps).__name__}")
    if not torch.isfinite(maps.detach()).all():
        raise IFSError("maps must be finite (a fit's step may have diverged: lower its learning rate)")
    check_contractive_maps(maps.detach().double().cpu())
    if not isinstance(probabilities, torch.Tensor) or probabilities.shape != (maps.shape[0],):
        raise IFSError(f"probabilities must be a tensor of shape ({maps.shape[0]},), one per map")
    p = probabilities.detach().double()
    if not (torch.isfinite(p).all() and (p > 0).all() and abs(float(p.sum()) - 1) < 1e-5):
        raise IFSError(f"probabilities must be finite, > 0 and sum to 1, got {p.tolist()}")


def splat(xy: torch.Tensor, weight: torch.Tensor, size: int, total: int) -> torch.Tensor:
    """Points ``(n, 2)`` with weights ``(n,)`` splatted bilinearly onto the ``(size, size)`` pixel centres, divided by
    ``total``; differentiable in both. Points whose four pixels are off the grid give the grid nothing."""
    u = (xy[:, 0] + 0.5) * size - 0.5          # column, with pixel c's centre at c
    v = (0.5 - xy[:, 1]) * size - 0.5          # row
    u0, v0 = u.detach().floor(), v.detach().floor()
    fu, fv = u - u0, v - v0
    flat = torch.zeros(size * size + 1, dtype=xy.dtype, device=xy.device)
    w = weight.to(xy.dtype) / total
    for du, dv, corner in ((0, 0, (1 - fu) * (1 - fv)), (1, 0, fu * (1 - fv)), (0, 1, (1 - fu) * fv),
                           (1, 1, fu * fv)):
        c, r = u0 + du, v0 + dv
        inside = (c >= 0) & (c < size) & (r >= 0) & (r < size)
        index = torch.where(inside, r * size + c, torch.full_like(c, size * size)).long()
        flat = flat.index_add(0, index, corner * w)
    return flat[:-1].view(size, size)


def splat_measure(maps: torch.Tensor, probabilities: torch.Tensor, size: int,
                  options: SplatOptions = SplatOptions()) -> torch.Tensor:
    """The invariant measure of ``maps`` with ``probabilities`` by the differentiable chaos game.

    Parameters
    ----------
    maps : torch.Tensor
        ``(m, 3, 3)`` (or ``(m, 2, 3)``) contractive maps in plane units; the image's dtype and device.
    probabilities : torch.Tensor
        ``(m,)``, > 0, summing to 1.
    size : int
        Pixels per side of the frame ``[-0.5, 0.5]²``.
    options : SplatOptions

    Returns
    -------
    torch.Tensor
        ``(size, size)`` mass per pixel, row 0 at the top, summing to the share of points in the frame;
        differentiable in ``maps`` and ``probabilities``.

    Raises
    ------
    IFSError
        On bad maps or probabilities (`check_maps`), a bad size or options, or more memory than the budget.
    """
    if not isinstance(options, SplatOptions):
        raise IFSError(f"options must be a SplatOptions, got {type(options).__name__}")
    check_int(size, "size", 1)
    check_maps(maps, probabilities)
    rows = -(-options.points // CHAINS) + options.depth
    n = (rows - options.depth) * CHAINS
    fine = size * options.supersample
    check_bytes(n * (BYTES_PER_POINT + options.depth * BYTES_PER_POINT_STEP + 4 * BYTES_PER_CORNER) + fine * fine * 16,
                f"a splat of {n:,} points at depth {options.depth} on {fine}² cells", "splat fewer points")
    points, picks = chain_points(maps, probabilities, rows, options.seed)
    xy, weight = replay(maps, probabilities.to(maps.device), points, picks, options.depth)
    image = splat(xy, weight, fine, n)
    k = options.supersample
    return image if k == 1 else image.view(size, k, size, k).sum((1, 3))


def coverage(density: torch.Tensor, scale: float) -> torch.Tensor:
    """A measure's image as a figure's: ``1 - exp(-density / scale)``, in [0, 1), differentiable.

    ``scale`` is the mass per pixel that reads ``1 - 1/e``: a pixel the chain visits is on the figure, however
    rarely, once its mass is well above it (`ifslib.splatting.config.COVERAGE` of the figure's mean mass a pixel).
    """
    if not scale > 0:
        raise IFSError(f"coverage's scale must be > 0, got {scale!r}")
    return -torch.expm1(-density / scale)
