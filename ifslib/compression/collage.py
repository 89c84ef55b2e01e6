"""The collage fit: each range block's best domain, isometry, contrast and mean by least squares.

For a range r and a domain d (both n pixels, centred: r - mean r, d - mean d), the contrast that
minimises ||r_c - s d_c||^2 is s = <r_c, d_c> / ||d_c||^2. Every domain and isometry is ranked at
once by the error of that s clipped to ``|s| <= s_max`` (one matrix product per chunk of ranges); the
best one's s is then quantized, and its error ||r_c||^2 - 2 s <r_c, d_c> + s^2 ||d_c||^2 (plus the
mean's rounding) is what the partition weighs.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import torch
import torch.nn.functional as F
from tqdm.auto import tqdm

from ..errors import IFSError
from .code import Code
from .config import CodeOptions
from .domains import pool_with_isometries
from .quantize import dequantize_m, dequantize_s, quantize_m, quantize_s, zero_s

#: ranges searched at once: chunk x (8 x domains) floats, about 32 MB for 4 px blocks of a 256² image.
CHUNK_PAIRS = 8_000_000


@dataclass(frozen=True)
class Fit:
    """Each range's best map: ``err`` (squared error, float64) and ``domain, iso, s_idx, m_idx``, all ``(R,)``."""

    err: torch.Tensor
    domain: torch.Tensor
    iso: torch.Tensor
    s_idx: torch.Tensor
    m_idx: torch.Tensor


def check_image(image) -> torch.Tensor:
    """A ``(h, w)`` array of gray levels in [0, 1] as a float tensor, or `IFSError` saying what is wrong."""
    image = torch.as_tensor(np.asarray(image) if not torch.is_tensor(image) else image)
    if image.ndim != 2 or min(image.shape) < 8:
        raise IFSError(f"expected a gray image (h, w) of at least 8 x 8 pixels, got shape {tuple(image.shape)}; "
                       "convert a colour image to gray first")
    if not image.is_floating_point():
        raise IFSError(f"expected gray levels as floats in [0, 1], got {image.dtype}; divide 8-bit pixels by 255")
    if not torch.isfinite(image).all() or image.min() < 0 or image.max() > 1:
        raise IFSError("gray levels must be finite and in [0, 1]; scale the image first")
    return image


def pad(image: torch.Tensor, options: CodeOptions) -> torch.Tensor:
    """``(h, w)`` -> ``(H, W)``, multiples of max_block, the last row and column repeated."""
    b = options.max_block
    h, w = image.shape
    H, W = -(-h // b) * b, -(-w // b) * b
    if (H, W) == (h, w):
        return image
    return F.pad(image[None, None], (0, W - w, 0, H - h), mode="replicate")[0, 0]


def ranges(image: torch.Tensor, size: int) -> torch.Tensor:
    """Every aligned ``size`` block of ``image`` ``(H, W)``, raster order: ``(H/size * W/size, size*size)``."""
    blocks = image.unfold(0, size, size).unfold(1, size, size)
    return blocks.reshape(-1, size * size)


def search(targets: torch.Tensor, domains: torch.Tensor, options: CodeOptions,
           nonflat: torch.Tensor | None = None, penalty: torch.Tensor | None = None) -> Fit:
    """The best domain, isometry and quantized contrast and mean for each range.

    Parameters
    ----------
    targets : torch.Tensor
        ``(R, n)`` range blocks, flattened.
    domains : torch.Tensor
        ``(8, D, n)`` the domain pool under each isometry (`domains.pool_with_isometries`).
    nonflat : torch.Tensor, optional
        ``(R,)`` bool: these ranges must keep a domain (s = 0 is not allowed), so that their bits stay
        the same; the others may also be stored flat.
    penalty : torch.Tensor, optional
        ``(R, D)`` what each domain's bits cost each range, in squared error (a price per bit times the
        bits): the domain of least error plus penalty wins (rate-distortion); ``err`` stays the error.

    Returns
    -------
    Fit
    """
    n = targets.shape[1]
    dc = domains.reshape(-1, n)
    dc = dc - dc.mean(1, keepdim=True)
    dd = (dc * dc).sum(1)
    mean = targets.mean(1)
    m_idx = quantize_m(mean, options)
    m_err = n * (mean - dequantize_m(m_idx, options, targets.dtype)) ** 2
    rc = targets - mean[:, None]
    rr = (rc * rc).sum(1)
    nonflat = torch.zeros(len(targets), dtype=torch.bool) if nonflat is None else nonflat
    inv_dd = 1 / dd.clamp_min(1e-12)
    chunk = max(1, CHUNK_PAIRS // max(1, len(dc)))
    best = [], []
    for start in range(0, len(targets), chunk):
        dot = rc[start:start + chunk] @ dc.T  # (chunk, 8D)
        # the error falls by 2 s (<r_c, d_c> - s ||d_c||^2 / 2) with the best |s| <= s_max (unquantized)
        s = (dot * inv_dd).clamp_(-options.s_max, options.s_max)
        gain = torch.addcmul(dot, s, dd, value=-0.5).mul_(s)  # half the error saved
        if penalty is not None:
            part = penalty[start:start + chunk]
            gain = (gain.view(len(part), -1, part.shape[1]) - 0.5 * part[:, None]).view(len(part), -1)
        _, k = gain.max(1)
        best[0].append(k)
        best[1].append(dot.gather(1, k[:, None])[:, 0])
    k, dot = (torch.cat(b) for b in best)
    s_idx = quantize_s(dot * inv_dd[k], options)
    forced = nonflat & (s_idx == zero_s(options))
    s_idx = torch.where(forced, s_idx + torch.where(dot >= 0, 1, -1), s_idx)
    s = dequantize_s(s_idx, options, targets.dtype)
    err = rr - 2 * s * dot + s * s * dd[k]
    count, keep = domains.shape[1], s_idx != zero_s(options)  # a flat block stores no domain: 0 by convention
    return Fit(err=(err.clamp_min(0) + m_err).double(), domain=(k % count) * keep, iso=(k // count) * keep,
               s_idx=s_idx, m_idx=m_idx)


def level_fits(image: torch.Tensor, options: CodeOptions, progress: bool = False) -> dict[int, Fit]:
    """The collage fit of every aligned block of every size of the padded ``image``: ``{size: Fit}``."""
    out = {}
    for size in tqdm(options.sizes, desc="collage search", unit="size", disable=not progress, leave=False):
        out[size] = search(ranges(image, size), pool_with_isometries(image, size), options)
    return out


def assemble(height: int, width: int, options: CodeOptions, fits: dict[int, Fit], leaves) -> Code:
    """The `Code` of the leaves ``[(size, y, x), ...]`` with each one's fit from ``fits``."""
    H, W = -(-height // options.max_block) * options.max_block, -(-width // options.max_block) * options.max_block
    size, y, x = (torch.tensor(c, dtype=torch.long) for c in zip(*leaves))
    fields = {name: torch.empty(len(size), dtype=torch.long) for name in ("domain", "iso", "s_idx", "m_idx")}
    for s in options.sizes:
        at = size == s
        if not at.any():
            continue
        row = (y[at] // s) * (W // s) + x[at] // s
        for name in fields:
            fields[name][at] = getattr(fits[s], name)[row]
    return Code(options, height, width, y, x, size, **fields)
