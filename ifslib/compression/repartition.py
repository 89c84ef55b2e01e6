"""The partition chosen by rate and distortion: quadtree and flat blocks for a domain pool, within a budget.

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

import torch
from tqdm.auto import tqdm

from .collage import Fit, ranges, search
from .config import CodeOptions
from .domains import pool_with_isometries
from .encode import grown
from .fields import code_fields, columns
from .partitions import Partition
from .quantize import dequantize_m, quantize_m, zero_s
from .rates import Choice, choose


def level_choices(target: torch.Tensor, pool_image: torch.Tensor, options: CodeOptions,
                  progress: bool = False) -> tuple[dict[int, Fit], dict[int, Fit]]:
    """Every aligned block of ``target`` ``(H, W)`` fitted with a domain from ``pool_image`` ``(H, W)`` and flat.

    Returns
    -------
    tuple
        ``({size: Fit with a domain}, {size: flat Fit})``, each over its size's grid in raster order.
    """
    mapped, flat = {}, {}
    for size in tqdm(options.sizes, desc="partition search", unit="size", disable=not progress, leave=False):
        blocks = ranges(target, size)
        mapped[size] = search(blocks, pool_with_isometries(pool_image, size), options,
                              torch.ones(len(blocks), dtype=torch.bool))
        m_idx = quantize_m(blocks.mean(1), options)
        err = ((blocks - dequantize_m(m_idx, options, blocks.dtype)[:, None]) ** 2).sum(1).double()
        zeros = torch.zeros_like(m_idx)
        flat[size] = Fit(err=err, domain=zeros, iso=zeros, s_idx=torch.full_like(m_idx, zero_s(options)), m_idx=m_idx)
    return mapped, flat


def partition(target: torch.Tensor, pool_image: torch.Tensor, height: int, width: int, options: CodeOptions,
              budget_bits: float, progress: bool = False) -> Choice:
    """The code of ``target`` ``(H, W)`` (padded; the image is ``height x width``) whose blocks map domains
    of ``pool_image`` ``(H, W)``, partition and flat blocks chosen by rate-distortion in ``budget_bits``
    (`rates.Choice`: the code and the price of a bit that chose it)."""
    return choose(level_choices(target, pool_image, options, progress), height, width, options, budget_bits)


#: squares split in four, at a rate (`partition`) or grown to a collage quality (`encode.grown`)
PARTITION = Partition("quadtree", rectangles=False, fields=code_fields, columns=columns, at_rate=partition,
                      at_quality=grown)
