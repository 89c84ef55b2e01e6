"""The domain pool (blocks twice a range's size, averaged down, on a lattice) and the 8 isometries.

A domain for ranges of ``size`` pixels is the ``2 size`` block at a lattice point ``(step * i, step * j)``,
averaged over 2 x 2 pixels down to ``size``; its index counts lattice points row by row. The step is
the range's size, doubled until the pool holds at most `config.MAX_DOMAINS` domains, so that the
search costs the same per block at any image size.
"""
from __future__ import annotations

import math

import torch
import torch.nn.functional as F

from .config import MAX_DOMAINS

#: the 8 isometries of a square: rotations by 0, 90, 180, 270 degrees, then the same after a transpose.
ISOMETRIES = 8
#: bits of an isometry's index.
ISOMETRY_BITS = 3


def isometry(blocks: torch.Tensor, k: int) -> torch.Tensor:
    """Isometry ``k`` (0-7) of square blocks ``(..., n, n)``: a transpose if k >= 4, then k % 4 quarter turns."""
    if k >= 4:
        blocks = blocks.transpose(-1, -2)
    return torch.rot90(blocks, k % 4, dims=(-2, -1))


def _positions(extent: int, size: int, step: int) -> int:
    return max(0, (extent - 2 * size) // step + 1)


def domain_step(height: int, width: int, size: int) -> int:
    """The lattice's step for ranges of ``size``: ``size`` doubled until at most MAX_DOMAINS domains remain."""
    step = size
    while _positions(height, size, step) * _positions(width, size, step) > MAX_DOMAINS:
        step *= 2
    return step


def lattice(height: int, width: int, size: int) -> tuple[int, int]:
    """Rows and columns of domain positions for ranges of ``size`` in a ``height x width`` image."""
    step = domain_step(height, width, size)
    return _positions(height, size, step), _positions(width, size, step)


def domain_count(height: int, width: int, size: int) -> int:
    """How many domains the pool holds for ranges of ``size`` (at least 1 for any image with a domain)."""
    rows, cols = lattice(height, width, size)
    return rows * cols


def domain_bits(height: int, width: int, size: int) -> int:
    """Bits of a domain index for ranges of ``size``."""
    return max(1, math.ceil(math.log2(max(2, domain_count(height, width, size)))))


def downsample(image: torch.Tensor) -> torch.Tensor:
    """``(h, w)`` -> ``(h // 2, w // 2)``, the mean of each 2 x 2 pixels (differentiable)."""
    return F.avg_pool2d(image[None, None], 2)[0, 0]


def pool(image: torch.Tensor, size: int) -> torch.Tensor:
    """Every domain for ranges of ``size``, averaged down: ``(rows * cols, size, size)``.

    Parameters
    ----------
    image : torch.Tensor
        ``(h, w)`` gray levels.
    size : int
        The range size (even).
    """
    half = downsample(image)
    rows, cols = lattice(*image.shape, size)
    step = domain_step(*image.shape, size) // 2
    blocks = half.unfold(0, size, step).unfold(1, size, step)  # (rows', cols', size, size)
    return blocks[:rows, :cols].reshape(rows * cols, size, size)


def pool_with_isometries(image: torch.Tensor, size: int) -> torch.Tensor:
    """All domains under all isometries, flattened: ``(8, D, size * size)``, isometry first."""
    blocks = pool(image, size)
    return torch.stack([isometry(blocks, k).reshape(len(blocks), -1) for k in range(ISOMETRIES)])
