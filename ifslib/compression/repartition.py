"""The partition chosen again for the decoder: quadtree and flat blocks by rate and decoded distortion.

The collage coder grows its quadtree by the collage's error. Here every aligned block of every size
is fitted again with its domain pool cut from the *decoded* image x* of the current code: a block's
map applied to x* is what the decoder will draw there, so its error against the original estimates
the block's share of the decoded error (exact but for the change it makes to other blocks' domains).
Each block may also be stored flat (its mean alone, 13 bits fewer for a 4 px block of a 256² image).
`partition.prune_to_budget` then chooses the tree and the flat blocks: the tree of least
``err + lam * bits``, exact for that price ``lam`` of a bit, at the smallest price (bisected) whose tree
fits in the budget. That tree has the least error of any tree of at most its own bits; it is close to,
but not always, the least error within the budget, since a price reaches only the trees on the lower
convex hull of (bits, error) and a few bits may go unspent. The caller decodes the result and keeps it
only if it decodes closer.
"""
from __future__ import annotations

import numpy as np
import torch
from tqdm.auto import tqdm

from .code import Code
from .config import CodeOptions
from .domains import ISOMETRY_BITS, domain_bits, pool_with_isometries
from .encode import Fit, assemble, ranges, search
from .partition import LeafChoice, leaves_in_order, prune_to_budget
from .quantize import dequantize_m, quantize_m, zero_s


def level_choices(target: torch.Tensor, pool_image: torch.Tensor, options: CodeOptions,
                  progress: bool = False) -> tuple[dict[int, Fit], dict[int, Fit], dict[int, LeafChoice]]:
    """Every aligned block of ``target`` ``(H, W)`` fitted with a domain from ``pool_image`` ``(H, W)`` and flat.

    Returns
    -------
    tuple
        ``({size: Fit with a domain}, {size: flat Fit}, {size: LeafChoice})``.
    """
    H, W = target.shape
    mapped, flat, choices = {}, {}, {}
    for size in tqdm(options.sizes, desc="partition search", unit="size", disable=not progress, leave=False):
        blocks = ranges(target, size)
        fit = search(blocks, pool_with_isometries(pool_image, size), options,
                     torch.ones(len(blocks), dtype=torch.bool))
        m_idx = quantize_m(blocks.mean(1), options)
        err = ((blocks - dequantize_m(m_idx, options, blocks.dtype)[:, None]) ** 2).sum(1).double()
        zeros = torch.zeros_like(m_idx)
        flat[size] = Fit(err=err, domain=zeros, iso=zeros, s_idx=torch.full_like(m_idx, zero_s(options)), m_idx=m_idx)
        mapped[size] = fit
        grid = (H // size, W // size)
        with_domain = options.s_bits + options.m_bits + ISOMETRY_BITS + domain_bits(H, W, size)
        choices[size] = LeafChoice(
            err=np.stack([fit.err.reshape(grid).numpy(), err.reshape(grid).numpy()]),
            bits=np.stack([np.full(grid, with_domain), np.full(grid, options.s_bits + options.m_bits)]))
    return mapped, flat, choices


def repartition(code: Code, target: torch.Tensor, decoded: torch.Tensor, budget_bits: int | None = None,
                progress: bool = False) -> Code:
    """A code of ``target`` with the partition and flat blocks chosen for ``decoded``, in at most ``budget_bits``.

    Parameters
    ----------
    code : Code
        The current code (its layout and size).
    target : torch.Tensor
        ``(H, W)`` the padded image being coded.
    decoded : torch.Tensor
        ``(H, W)`` the padded fixed point of ``code``: the domain pool.
    budget_bits : int, optional
        The most bits of flags and maps (default: ``code.bits()``).
    progress : bool

    Returns
    -------
    Code
        ``bits() <= budget_bits``: the least estimated error of any code of at most its own bits,
        not always the least within ``budget_bits`` (`partition.prune_to_budget`).
    """
    o = code.options
    H, W = target.shape
    mapped, flat, choices = level_choices(target, decoded, o, progress)
    tree = prune_to_budget(o, choices, code.bits() if budget_bits is None else budget_bits)
    fits = {}
    for size in o.sizes:
        f = torch.as_tensor(tree.flat[size].reshape(-1))
        a, b = mapped[size], flat[size]
        fits[size] = Fit(*(torch.where(f, getattr(b, name), getattr(a, name))
                           for name in ("err", "domain", "iso", "s_idx", "m_idx")))
    return assemble(code.height, code.width, o, fits, leaves_in_order(H, W, o, tree.split))
