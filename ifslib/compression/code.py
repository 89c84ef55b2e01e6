"""The partitioned IFS code: the partition's leaves (range blocks) and each one's quantized map.

Block ``i`` is the ``size[i]`` square at row ``y[i]``, column ``x[i]`` (a quadtree's), or, in an HV
partition's code, the ``height[i] x width[i]`` rectangle there (`rectangles`); its map takes domain
``domain[i]`` (for its size, `domains.pool`) under isometry ``iso[i]`` to
``s (D - mean D) + m``, with s and m stored as the level indices ``s_idx[i]`` and ``m_idx[i]``
(`quantize`). A block with s = 0 is flat: its mean alone, no domain and no isometry stored.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import torch

from ..errors import IFSError
from .config import CodeOptions
from .domains import ISOMETRY_BITS, domain_bits
from .fields import encode_fields
from .partitions import partition_of
from .quantize import dequantize_m, dequantize_s, zero_s


@dataclass(frozen=True)
class Code:
    """A partitioned IFS code of a ``height x width`` gray image.

    Attributes
    ----------
    options : CodeOptions
    height, width : int
        The image's size; the quadtree covers it padded up to a multiple of ``options.max_block``.
    y, x, size, domain, iso, s_idx, m_idx : torch.Tensor
        ``(L,)`` int64 each, one entry per range block, in the file's (depth-first) order. For an HV
        code ``size`` is each block's longer side.
    block_height, block_width : torch.Tensor, optional
        ``(L,)`` int64, an HV code's block sides (None for a quadtree's squares).
    """

    options: CodeOptions
    height: int
    width: int
    y: torch.Tensor
    x: torch.Tensor
    size: torch.Tensor
    domain: torch.Tensor
    iso: torch.Tensor
    s_idx: torch.Tensor
    m_idx: torch.Tensor
    block_height: torch.Tensor | None = None
    block_width: torch.Tensor | None = None

    def __post_init__(self):
        if partition_of(self.options).rectangles != (self.block_height is not None and self.block_width is not None):
            raise IFSError("a code of rectangles gives its blocks' heights and widths; a code of squares neither")

    @property
    def heights(self) -> torch.Tensor:
        """``(L,)`` each block's height."""
        return self.size if self.block_height is None else self.block_height

    @property
    def widths(self) -> torch.Tensor:
        """``(L,)`` each block's width."""
        return self.size if self.block_width is None else self.block_width

    @property
    def padded(self) -> tuple[int, int]:
        """The quadtree's ``(height, width)``: the image's, rounded up to a multiple of max_block."""
        b = self.options.max_block
        return -(-self.height // b) * b, -(-self.width // b) * b

    @property
    def flat(self) -> torch.Tensor:
        """``(L,)`` bool: blocks stored by their mean alone (s = 0)."""
        return self.s_idx == zero_s(self.options)

    def s(self, dtype=torch.float32) -> torch.Tensor:
        """``(L,)`` contrasts."""
        return dequantize_s(self.s_idx, self.options, dtype)

    def m(self, dtype=torch.float32) -> torch.Tensor:
        """``(L,)`` mean gray levels."""
        return dequantize_m(self.m_idx, self.options, dtype)

    def with_maps(self, **fields: torch.Tensor) -> "Code":
        """A copy with some of ``domain, iso, s_idx, m_idx`` replaced (the partition kept)."""
        bad = set(fields) - {"domain", "iso", "s_idx", "m_idx"}
        if bad:
            raise IFSError(f"with_maps changes only domain, iso, s_idx and m_idx, not {sorted(bad)}")
        return replace(self, **fields)

    def __len__(self) -> int:
        return len(self.size)

    def bits(self) -> int:
        """Bits of the quadtree flags and the blocks' maps: what the file holds after its header.

        Fixed-length fields (``coder="fixed"``) are counted (the file pads the last byte); range-coded
        ones are coded, about 20 ms for a 256² code.
        """
        o = self.options
        if o.coder != "fixed":
            return 8 * len(encode_fields(self).payload)
        height, width = self.padded
        total = 0
        for size in o.sizes:
            at = self.size == size
            n = int(at.sum())
            nonflat = int((at & ~self.flat).sum())
            total += n * (o.s_bits + o.m_bits) + nonflat * (ISOMETRY_BITS + domain_bits(height, width, size))
        return total + split_flag_count(self)


def split_flag_count(code: Code) -> int:
    """How many split flags the quadtree of ``code`` writes: one per node larger than min_block."""
    o = code.options
    # every leaf larger than min_block has a flag; each node split (a leaf's ancestors) has one too
    nodes = 0
    for size in o.sizes[:-1]:
        area = int((code.size[code.size <= size] ** 2).sum())  # pixels under nodes of this size or below
        nodes += area // (size * size)
    return nodes
