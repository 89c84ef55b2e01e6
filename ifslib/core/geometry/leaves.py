"""Expansion to depth K: every composed leaf map, with its inverse and scale, and a memory estimate."""
from __future__ import annotations

import math
import os
from dataclasses import dataclass

import torch

from ...errors import IFSError
from .ifs import IFS, check_depth
from .primitives import primitive_params
from .rules import map_scales, rule_maps, singular_values

#: Default memory budget in bytes for one distance field (override with ``IFSLIB_MEMORY_BUDGET_GB``).
DEFAULT_MEMORY_BUDGET = int(float(os.environ.get("IFSLIB_MEMORY_BUDGET_GB", "4")) * 2**30)

# Rough bytes per word and per pixel, measured loosely on CPU and rounded up.
_BYTES_PER_WORD = 400
_BYTES_PER_PIXEL = {"fast": 600, "brute": 120}


@dataclass
class Leaves:
    """All leaves of an IFS at one depth.

    Attributes
    ----------
    inverse : torch.Tensor
        ``(W, 2, 3)`` inverse affine map of each word (``W = m**K``).
    scale : torch.Tensor
        ``(W,)`` scale of each word's map (its smallest singular value when ``forward`` is given).
    params : torch.Tensor
        ``(p, PARAM_WIDTH)`` packed primitive geometry (see `ifslib.primitives.primitive_params`).
    kinds : tuple of str
        ``(p,)`` kind of each primitive.
    words_per_item : int
        0 for the leaves of one IFS. For a batch of ``B`` point sets of one pattern (see
        ``expand_batch`` of benchmarks/batch.py), ``m**K``: the words are then ``B * m**K`` (item-major), ``params`` is
        ``(B * p, PARAM_WIDTH)``, and leaf ids run over the whole batch, item ``b`` owning the ids
        ``b * m**K * p`` to ``(b + 1) * m**K * p - 1``.
    forward : torch.Tensor or None
        ``(W, 6)`` each word's forward map ``(a, b, tx, c, d, ty)``, for an IFS with ``affine``
        rules; None when every word is a similarity.
    """

    inverse: torch.Tensor
    scale: torch.Tensor
    params: torch.Tensor
    kinds: tuple[str, ...]
    words_per_item: int = 0
    forward: torch.Tensor | None = None

    @property
    def n_items(self) -> int:
        """Number of point sets: 1, or ``B`` for a batch."""
        return self.n_words // self.words_per_item if self.words_per_item else 1

    @property
    def n_words(self) -> int:
        return self.inverse.shape[0]

    @property
    def n_prims(self) -> int:
        return len(self.kinds)

    def __len__(self) -> int:
        return self.n_words * self.n_prims

    def detach(self) -> "Leaves":
        """The same leaves with no autograd history."""
        forward = None if self.forward is None else self.forward.detach()
        return Leaves(self.inverse.detach(), self.scale.detach(), self.params.detach(), self.kinds, self.words_per_item,
                      forward)


def word_geometry(words: torch.Tensor, similarity: bool) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor | None]:
    """What a leaf's distance needs of each word map: its inverse, its scale and, for affine words, the map itself.

    Parameters
    ----------
    words : torch.Tensor
        ``(..., W, 3, 3)`` composed maps.
    similarity : bool
        Whether every map is a similarity (then ``scale = sqrt|det|`` and no matrix is kept).

    Returns
    -------
    inverse : ``(..., W, 2, 3)``
    scale : ``(..., W)``: the similarity's scale, or the affine map's smallest singular value
    forward : ``(..., W, 6)`` or None: ``(a, b, tx, c, d, ty)``
    """
    inverse, scale = invert_similarities(words)
    if similarity:
        return inverse, scale, None
    return inverse, singular_values(words)[0], words[..., :2, :].flatten(-2)


def estimate_bytes(n_leaves_words: int, n_pixels: int, method: str = "fast") -> int:
    """Rough peak memory in bytes of one distance field with its backward pass.

    Parameters
    ----------
    n_leaves_words : int
        Number of words ``m**K``.
    n_pixels : int
        ``size**2``.
    method : {"fast", "brute"}
    """
    return n_leaves_words * _BYTES_PER_WORD + n_pixels * _BYTES_PER_PIXEL[method]


def check_bytes(need: int, what: str, advice: str) -> None:
    """Raise `IFSError` when ``need`` bytes exceed `DEFAULT_MEMORY_BUDGET`: "``what`` needs about ...: ``advice``"."""
    if need > DEFAULT_MEMORY_BUDGET:
        raise IFSError(f"{what} needs about {need / 2**30:.3g} GiB, over the memory budget of "
                       f"{DEFAULT_MEMORY_BUDGET / 2**30:.3g} GiB: {advice} (or raise IFSLIB_MEMORY_BUDGET_GB)")


def check_budget(ifs: IFS, depth: int, n_pixels: int, method: str, memory_budget: int | None) -> None:
    """Raise `IFSError` if the estimated memory exceeds the budget, before allocating anything."""
    budget = DEFAULT_MEMORY_BUDGET if memory_budget is None else int(memory_budget)
    m = len(ifs.rules)
    if m > 1 and depth * math.log2(m) > 60:  # more words than any memory holds: not worth the big integer
        raise IFSError(f"depth {depth} with {m} rules makes {m}^{depth} = {_power_text(m, depth)} leaf maps, far over "
                       f"the memory budget of {budget / 2**30:.2f} GiB. Lower the depth.")
    words = m ** depth
    need = estimate_bytes(words, n_pixels, method)
    if need > budget:
        raise IFSError(
            f"depth {depth} with {len(ifs.rules)} rules makes {words:,} leaf maps; with {n_pixels:,} pixels "
            f"this needs about {need / 2**30:.2f} GiB, over the memory budget of {budget / 2**30:.2f} GiB. "
            f"Lower the depth or size, or raise the memory budget (Budget(memory=...), or IFSLIB_MEMORY_BUDGET_GB).")


def compose_words(maps: torch.Tensor, depth: int) -> torch.Tensor:
    """All compositions ``T_{w_1} o ... o T_{w_K}`` of the maps.

    Parameters
    ----------
    maps : torch.Tensor
        ``(m, 3, 3)`` rule maps, or ``(B, m, 3, 3)`` for a batch.
    depth : int
        ``K``.

    Returns
    -------
    torch.Tensor
        ``(m**K, 3, 3)`` (``(B, m**K, 3, 3)``), words in lexicographic order (``w_1`` slowest).
    """
    batch = maps.shape[:-3]
    words = torch.eye(3, dtype=maps.dtype, device=maps.device).expand(*batch, 1, 3, 3)
    for _ in range(depth):
        words = (words[..., :, None, :, :] @ maps[..., None, :, :, :]).reshape(*batch, -1, 3, 3)
    return words


def invert_similarities(words: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """Closed-form inverses of affine maps, and their scales ``sqrt(|det A|)`` (a similarity's scale).

    Parameters
    ----------
    words : torch.Tensor
        ``(W, 3, 3)`` maps (any leading shape).

    Returns
    -------
    inverse : torch.Tensor
        ``(W, 2, 3)``.
    scale : torch.Tensor
        ``(W,)``, ``sqrt(|det A|)``.
    """
    a, b, c, d = words[..., 0, 0], words[..., 0, 1], words[..., 1, 0], words[..., 1, 1]
    tx, ty = words[..., 0, 2], words[..., 1, 2]
    det = a * d - b * c
    ia, ib, ic, id_ = d / det, -b / det, -c / det, a / det
    inverse = torch.stack([ia, ib, -(ia * tx + ib * ty), ic, id_, -(ic * tx + id_ * ty)], -1).view(*words.shape[:-2], 2, 3)
    return inverse, map_scales(words)


def expand(ifs: IFS, depth: int | None = None, *, device: torch.device | str = "cpu",
           dtype: torch.dtype | None = None, gradient: str = "exact") -> Leaves:
    """Expand an IFS to its depth-K leaves, differentiable in ``ifs.points``.

    Parameters
    ----------
    ifs : IFS
    depth : int, optional
        ``K``; ``ifs.depth`` when None.
    device, dtype
        Where and in what precision to build (``dtype`` None: that of ``ifs.points``).
    gradient : {"exact", "paper"}
        Gradient mode of the rules (see `ifslib.rules`).

    Returns
    -------
    Leaves
    """
    depth = ifs.depth if depth is None else check_depth(depth)
    ifs.validate()
    points = ifs.points.to(device=device, dtype=dtype or ifs.points.dtype)
    maps = rule_maps(points, ifs.rules, gradient)
    ifs.check_contractive(depth, maps)
    inverse, scale, forward = word_geometry(compose_words(maps, depth), ifs.is_similarity)
    return Leaves(inverse, scale, primitive_params(points, ifs.primitives),
                  tuple(p.kind for p in ifs.primitives), 0, forward)


def _power_text(m: int, depth: int, factor: int = 1) -> str:
    """``factor * m**depth`` in words: exact below 10^15, else its power of ten (without building the integer)."""
    digits = (depth * math.log10(m) if m > 1 else 0) + math.log10(max(factor, 1))
    return f"{factor * m ** depth:,}" if digits < 15 else f"about 10^{digits:.1f}"


def leaf_count_text(ifs: IFS, depth: int) -> str:
    """A one-line description of the leaf count, e.g. ``4^3 x 1 = 64 leaves`` (``4^1000 x 1 = about 10^602.1 leaves``)."""
    m, p = len(ifs.rules), len(ifs.primitives)
    return f"{m}^{check_depth(depth)} x {p} = {_power_text(m, depth, p)} leaves"


__all__ = ["Leaves", "expand", "compose_words", "invert_similarities", "estimate_bytes", "check_bytes", "check_budget",
           "DEFAULT_MEMORY_BUDGET", "leaf_count_text", "word_geometry"]
