"""`distance_field`: the signed distance from every pixel centre to the depth-K leaves, or to the attractor."""
from __future__ import annotations

from dataclasses import dataclass

import torch
from torch.utils.checkpoint import checkpoint

from ...errors import IFSError, check_int, check_positive
from ..geometry.attractor import (DEFAULT_SAMPLES, DEFAULT_TOLERANCE, AttractorLeaves, check_depth_or_attractor,
                                  check_window, is_attractor, leaf_points)
from ..geometry.expand import expand_attractor
from ..geometry.ifs import IFS
from ..geometry.leaves import Leaves, check_budget, expand
from .leaf_distance import sdf_dense, sdf_pairs
from .nearest import nearest_leaf, nearest_point, pixel_centres

#: The frame of a picture: the image plane ``[-0.5, 0.5]^2`` as a window ``(x0, y0, x1, y1)``.
FRAME = (-0.5, -0.5, 0.5, 0.5)

METHODS = ("fast", "brute", "sampled")

#: Below this pixel side (plane units), a float32 field of the attractor is computed in float64 (float32's
#: rounding through the words' maps moves the field by 1/100 of a pixel at a 100x zoom).
FLOAT32_PIXEL = 1e-4

#: Working memory of one brute-force chunk, in bytes.
BRUTE_CHUNK_BYTES = 64 * 2**20


@dataclass(frozen=True)
class Budget:
    """What one distance field may spend, each checked where it is used (its default when None): bytes of
    ``memory`` for the depth-K leaves, the attractor's ``leaves`` budget, and the ``samples`` of ``method="sampled"``."""

    memory: int | None = None
    leaves: int | None = None
    samples: int | None = None


def resolve_device(device: str | torch.device = "auto") -> torch.device:
    """``"auto"``: CUDA when present, else CPU; anything else is passed to `torch.device`."""
    if isinstance(device, str) and device == "auto":
        return torch.device("cuda" if torch.cuda.is_available() else "cpu")
    try:
        return torch.device(device)
    except (RuntimeError, TypeError) as exc:
        raise IFSError(f"unknown device {device!r}: use 'auto', 'cpu' or 'cuda'") from exc


def check_size(size) -> int:
    """Return ``size`` if it is an int >= 1, else raise `IFSError`."""
    return check_int(size, "size", 1, " (pixels per side)")


def _brute(leaves: Leaves, x: torch.Tensor, y: torch.Tensor) -> torch.Tensor:
    chunk = max(1, BRUTE_CHUNK_BYTES // (len(leaves) * x.element_size() * 16))
    tensors = (leaves.inverse, leaves.scale, leaves.params) + (() if leaves.forward is None else (leaves.forward,))

    def block(xc, yc, inverse, scale, params, forward=None):
        return sdf_dense(Leaves(inverse, scale, params, leaves.kinds, 0, forward), xc, yc).min(dim=1).values

    grad = torch.is_grad_enabled() and any(t.requires_grad for t in tensors)
    out = []
    for i in range(0, x.numel(), chunk):
        xc, yc = x[i:i + chunk], y[i:i + chunk]
        out.append(checkpoint(block, xc, yc, *tensors, use_reentrant=False) if grad else block(xc, yc, *tensors))
    return torch.cat(out)


def pixel_size(size: int, window: tuple[float, float, float, float] | None = None) -> float:
    """A pixel's side in plane units (the smaller side, for a window that is not square)."""
    x0, y0, x1, y1 = FRAME if window is None else check_window(window)
    return min(x1 - x0, y1 - y0) / check_size(size)


def point_distance(points: torch.Tensor, x: torch.Tensor, y: torch.Tensor) -> torch.Tensor:
    """``|(x, y) - points|`` row by row; finite where a query sits exactly on its point (gradient 0 there)."""
    sq = (x - points[:, 0]).square() + (y - points[:, 1]).square()
    return sq.clamp_min(torch.finfo(sq.dtype).tiny).sqrt()


def attractor_leaves_for(ifs: IFS, size: int, window=None, tolerance: float = DEFAULT_TOLERANCE, *,
                         device: str | torch.device = "cpu", dtype: torch.dtype | None = None,
                         gradient: str = "exact", max_leaves: int | None = None,
                         sampled: bool = False, samples: int | None = None) -> AttractorLeaves:
    """The attractor's leaves for a ``size x size`` picture of ``window``, within ``tolerance`` pixels (or
    ``samples`` random leaves of the cut)."""
    size = check_size(size)
    given = window
    window = FRAME if window is None else check_window(window)
    eps = check_positive(tolerance, "tolerance", " of pixels") * pixel_size(size, window)
    if sampled:
        samples = min(DEFAULT_SAMPLES, max(1 << 14, 2 * size * size)) if samples is None else samples
        return expand_attractor(ifs, eps, given, device=device, dtype=dtype, gradient=gradient, samples=samples)
    return expand_attractor(ifs, eps, window, max_leaves=max_leaves, device=device, dtype=dtype, gradient=gradient)


def _attractor_field(ifs: IFS, size: int, method: str, window, tolerance: float, dev: torch.device, dtype: torch.dtype,
                     gradient: str, max_leaves: int | None, samples: int | None) -> torch.Tensor:
    if dtype == torch.float32 and window is not None and pixel_size(size, window) < FLOAT32_PIXEL:
        # float32 rounds a leaf's point to about 1e-7 of the plane: a fair share of such a pixel
        return _attractor_field(ifs, size, method, window, tolerance, dev, torch.float64, gradient, max_leaves,
                                samples).to(dtype)
    leaves = attractor_leaves_for(ifs, size, window, tolerance, device=dev, dtype=dtype, gradient=gradient,
                                  max_leaves=max_leaves, sampled=method == "sampled", samples=samples)
    x, y = pixel_centres(size, dev, dtype, window)
    if method == "brute":  # every leaf at every pixel: the reference for the KD-tree
        sq = torch.cat([torch.cdist(torch.stack([x[i:i + 4096], y[i:i + 4096]], 1), leaves.points)
                        for i in range(0, x.numel(), 4096)])
        winner = sq.argmin(dim=1)
    else:
        winner = nearest_point(leaves.points, x, y)[0]
    # the minimum's gradient is its winner's: recompute the few winning leaves with autograd
    unique, inverse = torch.unique(winner, return_inverse=True)
    return point_distance(leaf_points(leaves, unique).index_select(0, inverse), x, y)


def distance_field(ifs: IFS, size: int, depth: int | str | None = None, method: str = "fast", *,
                   device: str | torch.device = "auto", dtype: torch.dtype | None = None,
                   gradient: str = "exact", tolerance: float = DEFAULT_TOLERANCE, window=None,
                   budget: Budget | None = None) -> torch.Tensor:
    """Signed distance ``(size, size)`` from every pixel centre to the depth-K leaf shapes, or to the attractor.

    Parameters
    ----------
    depth : int or "attractor", optional
        ``K`` (``ifs.depth`` when None), or the attractor within ``tolerance`` pixels (a ``window`` implies it).
    method : {"fast", "brute", "sampled"}
        Exact nearest-leaf search; every leaf at every pixel (the paper's algorithm); random leaves of the cut.
    gradient : {"exact", "paper"}
        ``"paper"`` cuts the gradient through segment rules' rotations, as the paper's code did.
    window : (x0, y0, x1, y1), optional
        For the attractor: the box of the plane the picture covers, its leaves refined for its pixels."""
    if method not in METHODS:
        raise IFSError(f"unknown method {method!r}; known methods: {', '.join(METHODS)}")
    check_size(size)
    if budget is not None and not isinstance(budget, Budget):
        raise IFSError(f"budget must be an ifslib.core.raster.distance.Budget, got a {type(budget).__name__}")
    budget = Budget() if budget is None else budget
    if window is not None and depth is None:
        depth = "attractor"
    depth = ifs.depth if depth is None else check_depth_or_attractor(depth)
    dtype = dtype or ifs.points.dtype
    if dtype not in (torch.float32, torch.float64):
        raise IFSError(f"dtype must be torch.float32 or torch.float64, got {dtype}")
    if is_attractor(depth):
        return _attractor_field(ifs, size, method, window, tolerance, resolve_device(device), dtype, gradient,
                                budget.leaves, budget.samples).view(size, size)
    if method == "sampled":
        raise IFSError(f"method 'sampled' draws the attractor: use depth='attractor' (not depth {depth})")
    if window is not None:
        raise IFSError(f"a window is drawn at full detail: use depth='attractor' (not depth {depth})")
    check_budget(ifs, depth, size * size, method, budget.memory)
    dev = resolve_device(device)
    leaves = expand(ifs, depth, device=dev, dtype=dtype, gradient=gradient)
    x, y = pixel_centres(size, dev, dtype)
    if method == "brute":
        field = _brute(leaves, x, y)
    else:
        winner = nearest_leaf(leaves, size).leaf
        field = sdf_pairs(leaves, x, y, winner)
    return field.view(size, size)
