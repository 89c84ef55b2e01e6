"""Rectangular range blocks: their 4 isometries, their domain pool, and the HV partition's split.

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

from typing import NamedTuple

import torch

from ..errors import IFSError
from .config import HV_STEP, MAX_DOMAINS
from .domains import ISOMETRIES, downsample, isometry

#: the isometries of a non-square block: identity, rows reversed, columns reversed, half turn.
RECTANGLE_ISOMETRIES = 4


class Block(NamedTuple):
    """A range block: the ``height x width`` rectangle whose top-left pixel is (``y``, ``x``)."""

    y: int
    x: int
    height: int
    width: int


def isometry_count(height: int, width: int) -> int:
    """8 isometries for a square block, 4 for a non-square one."""
    return ISOMETRIES if height == width else RECTANGLE_ISOMETRIES


def rectangle_isometry(blocks: torch.Tensor, k: int) -> torch.Tensor:
    """Isometry ``k`` of blocks ``(..., h, w)`` that keeps their shape.

    Square blocks take the 8 of `domains.isometry` (so a square code reads as before); non-square ones
    take ``k`` in 0-3: the identity, rows reversed, columns reversed, both (the half turn).
    """
    h, w = blocks.shape[-2:]
    if not 0 <= k < isometry_count(h, w):
        raise IFSError(f"isometry {k} does not apply to a {h} x {w} block (0-{isometry_count(h, w) - 1})")
    if h == w:
        return isometry(blocks, k)
    dims = [d for d, flip in ((-2, k & 1), (-1, k & 2)) if flip]
    return torch.flip(blocks, dims) if dims else blocks


def _positions(extent: int, side: int, step: int) -> int:
    return max(0, (extent - 2 * side) // step + 1)


def rectangle_step(height: int, width: int, block_height: int, block_width: int) -> tuple[int, int]:
    """The domain lattice's steps (rows, columns): the block's sides, both doubled until at most MAX_DOMAINS
    domains remain (for a square, `domains.domain_step`'s lattice)."""
    sy, sx = block_height, block_width
    while _positions(height, block_height, sy) * _positions(width, block_width, sx) > MAX_DOMAINS:
        sy, sx = 2 * sy, 2 * sx
    return sy, sx


def rectangle_lattice(height: int, width: int, block_height: int, block_width: int) -> tuple[int, int]:
    """Rows and columns of domain positions for ``block_height x block_width`` ranges."""
    sy, sx = rectangle_step(height, width, block_height, block_width)
    return _positions(height, block_height, sy), _positions(width, block_width, sx)


def rectangle_pool(image: torch.Tensor, block_height: int, block_width: int) -> torch.Tensor:
    """Every domain for ``block_height x block_width`` ranges, averaged down: ``(D, bh, bw)``.

    Parameters
    ----------
    image : torch.Tensor
        ``(H, W)`` gray levels (H and W even).
    block_height, block_width : int
        The range's sides (each at least 1, and twice each at most the image's).

    Returns
    -------
    torch.Tensor
        Domain ``i`` is the ``2 bh x 2 bw`` block at lattice point ``(i // cols, i % cols)``, row by row.
    """
    H, W = image.shape
    if min(block_height, block_width) < 1 or 2 * block_height > H or 2 * block_width > W:
        raise IFSError(f"a {block_height} x {block_width} block has no domain in a {H} x {W} image")
    sy, sx = rectangle_step(H, W, block_height, block_width)
    rows, cols = rectangle_lattice(H, W, block_height, block_width)
    # the lattice's steps are multiples of the block's sides, so even when the sides are: halve in place
    if sy % 2 or sx % 2:
        big = image.unfold(0, 2 * block_height, sy).unfold(1, 2 * block_width, sx)[:rows, :cols]
        blocks = big.reshape(rows, cols, block_height, 2, block_width, 2).mean((3, 5))
    else:
        half = downsample(image)
        blocks = half.unfold(0, block_height, sy // 2).unfold(1, block_width, sx // 2)[:rows, :cols]
    return blocks.reshape(rows * cols, block_height, block_width)


def cut_positions(side: int, min_side: int, step: int = HV_STEP) -> list[int]:
    """Where a block of ``side`` pixels may be cut: multiples of ``step`` leaving both parts ``min_side`` or more."""
    first = -(-min_side // step) * step
    return list(range(first, side - min_side + 1, step))


def edge_split(pixels: torch.Tensor, min_side: int, step: int = HV_STEP) -> tuple[int, int] | None:
    """Where the HV partition splits a block: ``(axis, position)``, or None when it cannot.

    Parameters
    ----------
    pixels : torch.Tensor
        ``(h, w)`` the block's gray levels.
    min_side : int
        The smallest side a part may have.
    step : int
        Split positions are multiples of it (fewer shapes to pool domains for, fewer bits to code).

    Returns
    -------
    tuple of int, or None
        ``axis`` 0 cuts between rows (parts ``position x w`` above and ``(h - position) x w`` below),
        1 between columns; None when neither side is at least ``2 * min_side``.
    """
    best = None
    for axis in (0, 1):
        n = pixels.shape[axis]
        cuts = torch.tensor(cut_positions(n, min_side, step), dtype=torch.long)
        if len(cuts) == 0:
            continue
        means = pixels.double().mean(1 - axis)  # one mean per row (axis 0) or per column (axis 1)
        jump = (means[cuts] - means[cuts - 1]).abs()
        # Fisher and Menlove's bias toward the middle: min(i, n - i) / (n - 1)
        score = jump * torch.minimum(cuts, n - cuts).double() / (n - 1)
        i = int(score.argmax())
        if best is None or score[i] > best[0]:
            best = (float(score[i]), axis, int(cuts[i]))
    return None if best is None else best[1:]


def split_block(block: Block, axis: int, position: int) -> tuple[Block, Block]:
    """The two parts of ``block`` cut ``position`` pixels from its top (axis 0) or left (axis 1)."""
    y, x, h, w = block
    if axis == 0:
        return Block(y, x, position, w), Block(y + position, x, h - position, w)
    return Block(y, x, h, position), Block(y, x + position, h, w - position)
