"""The collage coder: a code of the image at a rate (or a collage quality), every map fitted to the image itself.

At a rate (``bpp``) the partition and the flat blocks are chosen by rate and distortion
(`repartition.partition`, the collage's error against each field's coded bits). At a quality (the
collage's PSNR) the quadtree grows greedily where a split saves the most error per bit
(`partition.grow`) until the collage is that close. The least-squares fit itself is `collage`.
"""
from __future__ import annotations

import math

import torch

from ..errors import IFSError
from .code import Code
from .collage import Fit, assemble, check_image, level_fits, pad, ranges, search  # noqa: F401 - the coder's names
from .config import CodeOptions
from .domains import ISOMETRY_BITS, domain_bits, domain_count
from .fileformat import header_bytes
from .partition import LevelCost, grow, leaves_in_order, top_nodes
from .partitions import partition_of
from .quantize import quantize_m, zero_s
from .rates import Choice


def budget(bpp: float | None, quality: float | None, height: int, width: int,
           options: CodeOptions = CodeOptions()) -> tuple[float, float]:
    """``(bits for flags and maps, target squared error)`` from a rate in bits per pixel or a collage PSNR in dB."""
    if (bpp is None) == (quality is None):
        raise IFSError("give exactly one of bpp (bits per pixel) and quality (the collage's PSNR in dB)")
    if bpp is not None:
        if not (isinstance(bpp, (int, float)) and math.isfinite(bpp) and bpp > 0):
            raise IFSError(f"bpp must be a number > 0, got {bpp!r}")
        bits = bpp * height * width - 8 * header_bytes(options)
        return (bits - 7 if options.coder == "fixed" else bits), 0.0  # fixed fields pad the last byte
    if not (isinstance(quality, (int, float)) and math.isfinite(quality) and quality > 0):
        raise IFSError(f"quality must be a PSNR in dB > 0 (for instance 30), got {quality!r}")
    return float("inf"), height * width * 10 ** (-quality / 10)


def encode(image, options: CodeOptions = CodeOptions(), bpp: float | None = None,
           quality: float | None = None, progress: bool = False) -> Code:
    """The collage code of a gray image at a rate (``bpp``) or a collage quality (``quality``, PSNR in dB).

    `collage` with the price of a bit that chose it, which the attractor coder reuses.
    """
    return collage(image, options, bpp, quality, progress).code


def collage(image, options: CodeOptions = CodeOptions(), bpp: float | None = None,
            quality: float | None = None, progress: bool = False) -> Choice:
    """The collage code of a gray image at a rate (``bpp``) or a collage quality (``quality``, PSNR in dB).

    Parameters
    ----------
    image : array or torch.Tensor
        ``(h, w)`` gray levels in [0, 1], at least 8 x 8.
    options : CodeOptions
    bpp : float, optional
        The file's size in bits per pixel, header included (the quadtree grows until it is spent).
    quality : float, optional
        Grow the quadtree until the collage's PSNR reaches this many dB (or every block is smallest).
    progress : bool
        Show a bar over the block sizes.

    Returns
    -------
    rates.Choice
        The code; at a quality, with no price (``lam`` 0) and no models.
    """
    image = check_image(image)
    height, width = image.shape
    bits, target = budget(bpp, quality, height, width, options)
    padded = pad(image.float(), options)
    H, W = padded.shape
    if domain_count(H, W, options.max_block) == 0:
        raise IFSError(f"a {height} x {width} image has no domain for {options.max_block} px blocks; "
                       f"use max_block <= {min(H, W) // 2}")
    kind = partition_of(options)
    if bpp is None and kind.at_quality is None:
        raise IFSError(f"the {options.partition} partition is chosen for a rate: give bpp, not quality")
    least = coarsest(padded, height, width, options).bits()
    if bits < least:
        needed = least + (7 if options.coder == "fixed" else 0) + 8 * header_bytes(options)
        raise IFSError(f"{bpp} bpp is too few for this {height} x {width} image: its coarsest code takes "
                       f"{math.ceil(1000 * needed / (height * width)) / 1000:.3f} bpp; ask for at least that")
    if bpp is not None:
        return kind.at_rate(padded, padded, height, width, options, bits, progress)
    code = kind.at_quality(padded, height, width, options, bits, target, progress)
    return Choice(code, float("nan"), 0.0, None, None)


def grown(padded: torch.Tensor, height: int, width: int, options: CodeOptions, budget_bits: float,
          target_err: float, progress: bool = False) -> Code:
    """The quadtree's collage code of ``padded`` ``(H, W)`` grown where a split saves the most error per bit,
    until its squared error is ``target_err`` or its fields take ``budget_bits`` (`partition.grow`)."""
    H, W = padded.shape
    fits, costs = level_fits(padded, options, progress), {}
    for size, fit in fits.items():  # each block's error and bits, on its size's grid
        flat = fit.s_idx == zero_s(options)
        bits = options.s_bits + options.m_bits + (~flat).long() * (ISOMETRY_BITS + domain_bits(H, W, size))
        costs[size] = LevelCost(*(v.reshape(H // size, W // size).numpy() for v in (fit.err, bits)))
    split = grow(H, W, options, costs, budget_bits, target_err)
    return assemble(height, width, options, fits, leaves_in_order(H, W, options, split))


def coarsest(padded: torch.Tensor, height: int, width: int, options: CodeOptions) -> Code:
    """The code of fewest bits of ``padded`` ``(H, W)``: every top block flat, its mean alone."""
    m_idx = quantize_m(ranges(padded, options.max_block).mean(1), options)
    size, y, x = (torch.tensor(c, dtype=torch.long) for c in zip(*top_nodes(*padded.shape, options)))
    sides = dict(block_height=size, block_width=size) if partition_of(options).rectangles else {}
    return Code(options, height, width, y, x, size, 0 * m_idx, 0 * m_idx, torch.full_like(m_idx, zero_s(options)),
                m_idx, **sides)
