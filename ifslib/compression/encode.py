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
from .hv import hv_partition
from .hvfields import hv_columns
from .partition import LevelCost, grow, leaves_in_order, top_nodes
from .quantize import quantize_m, zero_s
from .rates import Choice
from .repartition import partition

def _costs(fits: dict[int, Fit], height: int, width: int, options: CodeOptions) -> dict[int, LevelCost]:
    """Each block's error and bits, on its size's grid."""
    out = {}
    for size, fit in fits.items():
        grid = (height // size, width // size)
        flat = fit.s_idx == zero_s(options)
        bits = options.s_bits + options.m_bits + (~flat).long() * (ISOMETRY_BITS + domain_bits(height, width, size))
        out[size] = LevelCost(err=fit.err.reshape(grid).numpy(), bits=bits.reshape(grid).numpy())
    return out


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
    if options.partition == "hv" and bpp is None:
        raise IFSError("an HV partition is chosen for a rate: give bpp, not quality")
    least = coarsest(padded, height, width, options).bits()
    if bits < least:
        needed = least + (7 if options.coder == "fixed" else 0) + 8 * header_bytes(options)
        raise IFSError(f"{bpp} bpp is too few for this {height} x {width} image: its coarsest code takes "
                       f"{math.ceil(1000 * needed / (height * width)) / 1000:.3f} bpp; ask for at least that")
    if options.partition == "hv":
        return Choice(hv_partition(padded, padded, height, width, options, bits), float("nan"), 0.0, None, None)
    if bpp is not None:
        return partition(padded, padded, height, width, options, bits, progress)
    fits = level_fits(padded, options, progress)
    split = grow(H, W, options, _costs(fits, H, W, options), bits, target)
    code = assemble(height, width, options, fits, leaves_in_order(H, W, options, split))
    return Choice(code, float("nan"), 0.0, None, None)


def coarsest(padded: torch.Tensor, height: int, width: int, options: CodeOptions) -> Code:
    """The code of fewest bits of ``padded`` ``(H, W)``: every top block flat, its mean alone."""
    blocks = ranges(padded, options.max_block)
    m_idx = quantize_m(blocks.mean(1), options)
    zeros = torch.zeros_like(m_idx)
    fit = Fit(err=zeros.double(), domain=zeros, iso=zeros, s_idx=torch.full_like(m_idx, zero_s(options)), m_idx=m_idx)
    if options.partition == "hv":
        b = options.max_block
        rows = [(y, x, b, b, 0, 0, zero_s(options), int(m)) for (_, y, x), m in zip(top_nodes(*padded.shape, options), m_idx)]
        return Code(options, height, width, **hv_columns(rows))
    return assemble(height, width, options, {options.max_block: fit}, top_nodes(*padded.shape, options))
