"""Sampled leaves of the attractor (`sample_attractor`), for attractors whose certified cut has too many leaves."""
from __future__ import annotations

import math

import torch

from ...errors import IFSError, check_positive
from .attractor import (AttractorLeaves, apply_maps, prepare_maps, word_maps, attractor_leaves,
                        check_window)
from .rules import chaos_probabilities, singular_values
from .words import DenseWords


_UNIFORMS: dict = {}
#: `sample_attractor` refuses maps whose walkers would need longer words than this (a scale near 1:
#: ``n`` walkers keep ``n`` uniforms per letter).
MAX_WORD_LENGTH = 512


def _uniforms(seed: int, n: int, cols: int) -> torch.Tensor:
    """``(n, cols)`` float64 uniforms, cached and drawn column by column, so the same ``(seed, n)`` gives the same
    ones whatever was asked before (a fit's sampled leaves do not depend on earlier fits)."""
    cached = _UNIFORMS.get((seed, n))
    if cached is None or cached.shape[1] < cols:
        generator = torch.Generator().manual_seed(seed)
        cached = torch.rand(max(cols, 16), n, dtype=torch.float64, generator=generator).T.contiguous()
        if len(_UNIFORMS) > 8:
            _UNIFORMS.clear()
        _UNIFORMS[(seed, n)] = cached
    return cached[:, :cols]


def _compose_rows(a: torch.Tensor, b: torch.Tensor) -> torch.Tensor:
    """Row by row ``a[i] o b[i]``: ``(N, 2, 3)`` maps after ``(N, 3, 3)`` maps, ``(N, 2, 3)`` (elementwise, no batched matmul)."""
    a0, a1 = a[:, :, 0:1], a[:, :, 1:2]  # (N, 2, 1)
    return a0 * b[:, None, 0, :] + a1 * b[:, None, 1, :] + torch.nn.functional.pad(a[:, :, 2:3], (2, 0))


def sample_attractor(maps: torch.Tensor, tolerance: float, n: int, seed: int = 0, rules=None,
                     window=None) -> AttractorLeaves:
    """``n`` leaves of the cut of `attractor_leaves`, drawn at random: a chaos game on the word tree.

    Each of ``n`` walkers descends the word tree from the root, choosing map ``i`` with the chaos
    game's probability (`chaos_probabilities`: in proportion to
    ``|det L_i|``, with a floor), and stops at the first word with ``||L_w|| R <= tolerance``: it
    ends on a leaf of the certified cut. So every sampled leaf is within ``tolerance`` of the
    attractor (the field from them is never below ``d(x, A) - tolerance``), and, where the
    walkers have come, the attractor is within ``tolerance`` of them; unlike the full cut, the
    number of leaves is ``n`` however much the copies overlap (24 overlapping maps of a silhouette
    need millions of leaves for the certified cut at a pixel's tolerance, and 65,536 samples
    cover it several times per pixel). This is how Tu et al. (AAAI 2023) and Djeacoumar et al.
    (CGF 2025) fit attractors; here every leaf keeps its word, so the gradient is exact for the
    sampled points.

    Parameters
    ----------
    maps : torch.Tensor
        ``(m, 3, 3)`` contracting maps, with or without autograd.
    tolerance : float
        ``ε`` in plane units.
    n : int
        Number of walkers (leaves; some may repeat).
    seed : int
        Seeds the walkers' choices: the same seed gives the same digits, so leaves move smoothly
        with the maps from one fit step to the next.
    rules : sequence of Rule, optional
        The rules the maps come from, named in the message of a map that does not contract.
    window : (x0, y0, x1, y1), optional
        Confine the walkers to the copies of the attractor about half this box's size that may hold
        the nearest point of one of its points (`_walker_starts`): a 1000x zoom gets as many leaves
        as the frame, where walkers from the root would almost all land outside it.

    Returns
    -------
    AttractorLeaves
    """
    tolerance = check_positive(tolerance, "tolerance", " (plane units)")
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise IFSError(f"the number of sampled leaves must be an integer >= 1, got {n!r}")
    if window is not None:
        window = check_window(window)
    work, largest, centre_grad, radius = prepare_maps(maps, rules)
    m, device = work.shape[0], work.device
    with torch.no_grad():
        centre = centre_grad.detach()
        # the deepest a walker can go: every step shrinks its error by at least the largest scale
        longest = max(1, math.ceil(math.log(tolerance / radius) / math.log(float(largest.max())))) if radius > tolerance else 0
        if longest > MAX_WORD_LENGTH:
            raise IFSError(f"a map contracts too slowly (largest scale {float(largest.max()):.6f}): sampled leaves would "
                           f"need words of {longest} maps, more than {MAX_WORD_LENGTH}")
        # inverse-CDF draws from fixed uniforms: the same seed gives the same words while the maps move
        cdf = chaos_probabilities(work).cumsum(0)
        first = 0 if window is None else 1  # a window's walkers draw their copy from the first column
        uniforms = _uniforms(int(seed), n, max(longest, 1) + first)
        digits = torch.searchsorted(cdf[:-1].contiguous(), uniforms[:, first:].contiguous()).to(device)
        current, error, prefix = _walker_starts(work, radius, n, window, tolerance, uniforms[:, 0], rules)
        length = torch.zeros(n, dtype=torch.long, device=device)
        active = error > tolerance
        for k in range(longest):
            idx = active.nonzero().flatten()
            if not idx.numel():
                break
            composed = _compose_rows(current[idx], work[digits[idx, k]])
            current[idx] = composed
            length[idx] = k + 1
            error[idx] = singular_values(composed)[1] * radius
            active[idx] = error[idx] > tolerance
        depth = int(length.max())
        steps = torch.arange(depth, device=device)
        words = torch.where(steps[None] < length[:, None], digits[:, :depth], m).to(prefix.dtype)
        points = apply_maps(current, centre)
    return AttractorLeaves(points, error, DenseWords(_join(prefix, words, m)), maps, centre_grad, radius,
                           float(tolerance))


def _walker_starts(work: torch.Tensor, radius: float, n: int, window, tolerance: float, uniform: torch.Tensor, rules):
    """Where `sample_attractor`'s ``n`` walkers start: their maps ``(n, 2, 3)``, errors ``(n,)`` and words ``(n, K0)``:
    the root, or for a window copies drawn with their words' probabilities from ``uniform``."""
    m, dtype, device = work.shape[0], work.dtype, work.device
    word_dtype = torch.uint8 if m < 255 else torch.int16
    if window is None:
        return (torch.eye(3, dtype=dtype, device=device)[None, :2].repeat(n, 1, 1),
                torch.full((n,), radius, dtype=dtype, device=device),
                torch.empty((n, 0), dtype=word_dtype, device=device))
    scale = max(tolerance, math.hypot(window[2] - window[0], window[3] - window[1]) / 4)
    roots = attractor_leaves(work, scale, window, rules=rules)
    words = roots.words
    probability = torch.cat([chaos_probabilities(work), torch.ones(1, dtype=torch.float64, device=device)])
    weight = probability[words.long()].prod(1)  # the padding digit m has probability 1
    cdf = (weight.cumsum(0) / weight.sum())[:-1].contiguous()
    pick = torch.searchsorted(cdf, uniform.contiguous()).to(device)
    return word_maps(work, words.index_select(0, pick)), roots.error[pick].clone(), words[pick]


def _join(prefix: torch.Tensor, suffix: torch.Tensor, m: int) -> torch.Tensor:
    """Words ``(n, K0)`` and ``(n, K1)``, each padded with ``m``, joined into ``(n, K)`` words padded at the end."""
    if not prefix.shape[1]:
        return suffix
    joined = torch.cat([prefix, suffix], 1)
    order = (joined == m).to(torch.uint8).argsort(dim=1, stable=True)
    joined = joined.gather(1, order)
    return joined[:, :int((joined != m).sum(1).max())]


__all__ = ["MAX_WORD_LENGTH", "sample_attractor"]
