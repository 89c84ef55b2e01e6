"""`distance_field`: the signed distance from every pixel centre to the depth-K leaves.

The distance of the union is the minimum over leaves, and the (sub)gradient of a minimum is the
gradient of its winner. So the ``"fast"`` method finds each pixel's nearest leaf with no autograd
(`ifslib.nearest`), then evaluates the distance to that one leaf with autograd: value and gradient
are those of the full minimum, and memory is O(pixels + leaves) rather than O(pixels x leaves).

The ``"brute"`` method is the paper's algorithm as written, every leaf at every pixel, kept as the
reference. It runs in chunks of pixels under activation checkpointing, so its memory stays bounded
while autograd still differentiates the true minimum.

Inside overlapping closed shapes (boxes, disks, thick segments) the minimum of the leaves' signed
distances is what the paper computes; outside the union it is the exact distance to the union.
"""
from __future__ import annotations

import torch
from torch.utils.checkpoint import checkpoint

from ..errors import IFSError, check_int
from ..geometry.ifs import IFS, check_depth
from ..geometry.leaves import Leaves, check_budget, expand, expand_batch, sdf_dense, sdf_pairs
from .nearest import nearest_leaf, pixel_centres

METHODS = ("fast", "brute")

#: Working memory of one brute-force chunk, in bytes.
BRUTE_CHUNK_BYTES = 64 * 2**20


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


def distance_field(ifs: IFS, size: int, depth: int | None = None, method: str = "fast", *,
                   device: str | torch.device = "auto", dtype: torch.dtype | None = None,
                   gradient: str = "exact", memory_budget: int | None = None) -> torch.Tensor:
    """Signed distance from every pixel centre to the union of the depth-K leaf shapes.

    Parameters
    ----------
    ifs : IFS
        The fractal; the result is differentiable in ``ifs.points``.
    size : int
        Image side in pixels; pixel centres follow CONVENTIONS.md (row 0 at the top).
    depth : int, optional
        Number of Hutchinson steps ``K`` (``ifs.depth`` when None).
    method : {"fast", "brute"}
        ``"fast"`` (default): exact nearest-leaf search, then autograd through the winner only.
        ``"brute"``: every leaf at every pixel (the paper's algorithm), the reference.
    device : {"auto", "cpu", "cuda"} or torch.device
        ``"auto"`` uses CUDA when present.
    dtype : torch.dtype, optional
        float32 or float64; that of ``ifs.points`` when None (float32 by default).
    gradient : {"exact", "paper"}
        ``"paper"`` cuts the gradient through segment rules' rotations, as the paper's code did.
    memory_budget : int, optional
        Bytes; the estimate is checked before anything is allocated.

    Returns
    -------
    torch.Tensor
        ``(size, size)`` signed distances in plane units.

    Raises
    ------
    IFSError
        Unknown method or device, bad size or depth, a degenerate or non-contractive rule, NaN
        points, or an estimate over the memory budget.
    """
    if method not in METHODS:
        raise IFSError(f"unknown method {method!r}; known methods: {', '.join(METHODS)}")
    check_size(size)
    depth = ifs.depth if depth is None else check_depth(depth)
    dtype = dtype or ifs.points.dtype
    if dtype not in (torch.float32, torch.float64):
        raise IFSError(f"dtype must be torch.float32 or torch.float64, got {dtype}")
    check_budget(ifs, depth, size * size, method, memory_budget)
    dev = resolve_device(device)
    leaves = expand(ifs, depth, device=dev, dtype=dtype, gradient=gradient)
    x, y = pixel_centres(size, dev, dtype)
    if method == "brute":
        field = _brute(leaves, x, y)
    else:
        winner = nearest_leaf(leaves, size).leaf
        field = sdf_pairs(leaves, x, y, winner)
    return field.view(size, size)


def distance_fields(ifs: IFS, points: torch.Tensor, size: int, depth: int | None = None, *,
                    gradient: str = "exact") -> torch.Tensor:
    """The distance fields of a batch of point sets of one pattern, in one computation.

    Each item is what `distance_field` gives for ``ifs`` with that item's points (method
    ``"fast"``): one nearest-leaf search over the whole batch, each pixel searching only its own
    item's leaves, then autograd through the winners.

    Parameters
    ----------
    ifs : IFS
        The pattern (rules, primitives); its own points are not used.
    points : torch.Tensor
        ``(B, n, 2)`` on the device and in the dtype to compute in. Every item must make
        non-degenerate, contractive rules (see `ifslib.leaves.expand_batch`).
    size : int
    depth : int, optional
        ``ifs.depth`` when None.
    gradient : {"exact", "paper"}

    Returns
    -------
    torch.Tensor
        ``(B, size, size)``, differentiable in ``points``.
    """
    check_size(size)
    leaves = expand_batch(ifs, points, depth, gradient=gradient)
    x, y = pixel_centres(size, points.device, points.dtype)
    n_items = points.shape[0]
    # smaller chunks than one field's: a batch's pair lists outgrow the cache
    winner = nearest_leaf(leaves, size, max_pairs=1 << 18).leaf
    return sdf_pairs(leaves, x.repeat(n_items), y.repeat(n_items), winner).view(n_items, size, size)
