"""Expansion to depth K: every composed leaf map, with its inverse and scale, and a memory estimate.

A leaf is a word ``w = (w_1, ..., w_K)`` of rule indices together with a primitive ``p``; its shape
is ``T_{w_1} o ... o T_{w_K}(D_p)``. Leaves are numbered ``leaf = word * n_prims + p`` with words in
lexicographic order, so the primitive varies fastest.

For a similarity ``T`` of scale ``s`` the distance law is ``d_{T(S)}(x) = s * d_S(T^{-1} x)`` (the
paper prints ``1/s``: an erratum), so each word needs only its inverse map and its scale.
"""
from __future__ import annotations

import os
from dataclasses import dataclass

import torch

from .errors import IFSError
from .ifs import IFS, check_depth
from .primitives import primitive_params
from .rules import map_scales, rule_maps

#: Default memory budget in bytes for one distance field (override with ``IFSLIB_MEMORY_BUDGET_GB``).
DEFAULT_MEMORY_BUDGET = int(float(os.environ.get("IFSLIB_MEMORY_BUDGET_GB", "4")) * 2**30)

# Rough bytes per word (maps of every level, inverse, scale, autograd's saved tensors) and per
# pixel (coordinates, search pairs, the winner's gathered map and its gradient), measured loosely
# on CPU and rounded up.
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
        ``(W,)`` scale of each word's map.
    params : torch.Tensor
        ``(p, 5)`` packed primitive geometry (see `ifslib.primitives.primitive_params`).
    kinds : tuple of str
        ``(p,)`` kind of each primitive.
    """

    inverse: torch.Tensor
    scale: torch.Tensor
    params: torch.Tensor
    kinds: tuple[str, ...]

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
        return Leaves(self.inverse.detach(), self.scale.detach(), self.params.detach(), self.kinds)


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


def check_budget(ifs: IFS, depth: int, n_pixels: int, method: str, memory_budget: int | None) -> None:
    """Raise `IFSError` if the estimated memory exceeds the budget, before allocating anything."""
    budget = DEFAULT_MEMORY_BUDGET if memory_budget is None else int(memory_budget)
    words = len(ifs.rules) ** depth
    need = estimate_bytes(words, n_pixels, method)
    if need > budget:
        raise IFSError(
            f"depth {depth} with {len(ifs.rules)} rules makes {words:,} leaf maps; with {n_pixels:,} pixels "
            f"this needs about {need / 2**30:.2f} GiB, over the memory budget of {budget / 2**30:.2f} GiB. "
            f"Lower the depth or size, or raise memory_budget (or IFSLIB_MEMORY_BUDGET_GB).")


def compose_words(maps: torch.Tensor, depth: int) -> torch.Tensor:
    """All compositions ``T_{w_1} o ... o T_{w_K}`` of the maps.

    Parameters
    ----------
    maps : torch.Tensor
        ``(m, 3, 3)`` rule maps.
    depth : int
        ``K``.

    Returns
    -------
    torch.Tensor
        ``(m**K, 3, 3)``, words in lexicographic order (``w_1`` slowest).
    """
    words = torch.eye(3, dtype=maps.dtype, device=maps.device)[None]
    for _ in range(depth):
        words = (words[:, None] @ maps[None]).reshape(-1, 3, 3)
    return words


def invert_similarities(words: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """Closed-form inverses and scales of affine maps.

    Parameters
    ----------
    words : torch.Tensor
        ``(W, 3, 3)`` maps.

    Returns
    -------
    inverse : torch.Tensor
        ``(W, 2, 3)``.
    scale : torch.Tensor
        ``(W,)``, ``sqrt(|det A|)``.
    """
    a, b, c, d = words[:, 0, 0], words[:, 0, 1], words[:, 1, 0], words[:, 1, 1]
    tx, ty = words[:, 0, 2], words[:, 1, 2]
    det = a * d - b * c
    ia, ib, ic, id_ = d / det, -b / det, -c / det, a / det
    inverse = torch.stack([ia, ib, -(ia * tx + ib * ty), ic, id_, -(ic * tx + id_ * ty)], -1).view(-1, 2, 3)
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
    inverse, scale = invert_similarities(compose_words(maps, depth))
    return Leaves(inverse, scale, primitive_params(points, ifs.primitives),
                  tuple(p.kind for p in ifs.primitives))


def leaf_count_text(ifs: IFS, depth: int) -> str:
    """A one-line description of the leaf count, e.g. ``4^3 x 1 = 64 leaves``."""
    m, p = len(ifs.rules), len(ifs.primitives)
    return f"{m}^{depth} x {p} = {m ** depth * p:,} leaves"


__all__ = ["Leaves", "expand", "compose_words", "invert_similarities", "estimate_bytes", "check_budget",
           "DEFAULT_MEMORY_BUDGET", "leaf_count_text"]



def _gather_words(leaves: Leaves, leaf: torch.Tensor):
    """Per-pair inverse-map rows, scale and primitive index for leaf ids ``leaf`` (N,)."""
    p = leaves.n_prims
    word = leaf if p == 1 else torch.div(leaf, p, rounding_mode="floor")
    inv = leaves.inverse.reshape(-1, 6).index_select(0, word)
    scale = leaves.scale.index_select(0, word)
    prim = None if p == 1 else leaf - word * p
    return inv, scale, prim


def sdf_pairs(leaves: Leaves, x: torch.Tensor, y: torch.Tensor, leaf: torch.Tensor) -> torch.Tensor:
    """Signed distance from point ``i`` to leaf ``leaf[i]``, for each i.

    Parameters
    ----------
    leaves : Leaves
    x, y : torch.Tensor
        ``(N,)`` query coordinates (plane units).
    leaf : torch.Tensor
        ``(N,)`` leaf ids (``word * n_prims + primitive``).

    Returns
    -------
    torch.Tensor
        ``(N,)`` distances ``s_w * d_p(T_w^{-1} x)``, differentiable in the leaves' tensors.
    """
    from .primitives import local_sdf

    inv, scale, prim = _gather_words(leaves, leaf)
    qx = inv[:, 0] * x + inv[:, 1] * y + inv[:, 2]
    qy = inv[:, 3] * x + inv[:, 4] * y + inv[:, 5]
    if prim is None:
        return scale * local_sdf(leaves.kinds[0], qx, qy, leaves.params[0])
    out = torch.zeros_like(qx)
    kind_codes = torch.tensor([sorted(set(leaves.kinds)).index(k) for k in leaves.kinds], device=leaf.device)
    for code, kind in enumerate(sorted(set(leaves.kinds))):
        sel = (kind_codes[prim] == code).nonzero().flatten()
        if sel.numel():
            d = local_sdf(kind, qx[sel], qy[sel], leaves.params[prim[sel]])
            out = out.index_put((sel,), scale[sel] * d)
    return out


def sdf_dense(leaves: Leaves, x: torch.Tensor, y: torch.Tensor) -> torch.Tensor:
    """Signed distance from every point to every leaf (the paper's algorithm).

    Parameters
    ----------
    leaves : Leaves
    x, y : torch.Tensor
        ``(C,)`` query coordinates.

    Returns
    -------
    torch.Tensor
        ``(C, L)`` distances, leaf ids along the second axis.
    """
    from .primitives import local_sdf

    inv = leaves.inverse.reshape(-1, 6)
    x, y = x[:, None], y[:, None]
    qx = inv[:, 0] * x + inv[:, 1] * y + inv[:, 2]
    qy = inv[:, 3] * x + inv[:, 4] * y + inv[:, 5]
    per_prim = [leaves.scale * local_sdf(kind, qx, qy, leaves.params[j]) for j, kind in enumerate(leaves.kinds)]
    return torch.stack(per_prim, -1).reshape(x.shape[0], -1)


__all__ += ["sdf_pairs", "sdf_dense"]
