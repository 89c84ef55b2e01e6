"""The distance from points to leaves: one leaf's, and the lookups of many (point, leaf) pairs."""
from __future__ import annotations

import torch

from ...errors import IFSError
from ..geometry.leaves import Leaves
from ..geometry.primitives import PARAM_WIDTH
from ..geometry.shapes import SHAPES


def _pull_back(inverse: torch.Tensor, x: torch.Tensor, y: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """``q = T_w^-1 x``, the points in the primitive's frame, for the inverse maps ``inverse`` ``(..., 6)``."""
    return (inverse[..., 0] * x + inverse[..., 1] * y + inverse[..., 2],
            inverse[..., 3] * x + inverse[..., 4] * y + inverse[..., 5])


def leaf_sdf(kind: str, x: torch.Tensor, y: torch.Tensor, inverse: torch.Tensor, scale: torch.Tensor,
             params: torch.Tensor, forward: torch.Tensor | None) -> torch.Tensor:
    """A leaf's signed distance at ``x``: ``scale * d(T_w^-1 x)`` for a similarity word, and
    the distance in the plane (`ifslib.core.geometry.shapes.Shape.affine`) when the word's map ``forward``
    (``(..., 6)``) is given. ``inverse`` is ``(..., 6)``, the word's inverse map; every tensor broadcasts against
    ``x``."""
    qx, qy = _pull_back(inverse, x, y)
    if forward is None:
        return scale * SHAPES[kind].local(qx, qy, params.unbind(-1))
    return SHAPES[kind].affine(x, y, qx, qy, forward, scale, params.unbind(-1))


def _gather_words(leaves: Leaves, leaf: torch.Tensor):
    """Per-pair inverse-map rows, scale, forward rows (None for similarities), local primitive index and ``params``
    row for leaf ids ``leaf`` (the last two None when every pair uses ``params[0]``)."""
    p = leaves.n_prims
    word = leaf if p == 1 else torch.div(leaf, p, rounding_mode="floor")
    inv = leaves.inverse.reshape(-1, 6).index_select(0, word)
    scale = leaves.scale.index_select(0, word)
    forward = None if leaves.forward is None else leaves.forward.index_select(0, word)
    prim = None if p == 1 else leaf - word * p
    row = prim
    if leaves.words_per_item:
        item = torch.div(word, leaves.words_per_item, rounding_mode="floor")
        row = item * p if prim is None else item * p + prim
    return inv, scale, forward, prim, row


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
    inv, scale, forward, prim, row = _gather_words(leaves, leaf)
    kinds = sorted(set(leaves.kinds))
    if len(kinds) == 1:
        # one row per pair even when all share params[0]: the gradient of a row broadcast to every
        # pixel is one sum over all of them, which torch splits by thread count; index_select's is not
        row = torch.zeros_like(leaf) if row is None else row
        params = leaves.params.index_select(0, row)
        return leaf_sdf(kinds[0], x, y, inv, scale, params, forward)
    out = torch.zeros_like(x)
    kind_codes = torch.tensor([kinds.index(k) for k in leaves.kinds], device=leaf.device)
    for code, kind in enumerate(kinds):
        sel = (kind_codes[prim] == code).nonzero().flatten()
        if sel.numel():
            d = leaf_sdf(kind, x[sel], y[sel], inv[sel], scale[sel], leaves.params[row[sel]],
                         None if forward is None else forward[sel])
            out = out.index_put((sel,), d)
    return out


#: The rows of a `leaf_table` before a word's forward map: 6 inverse-map entries, the scale, the packed primitive.
_GEOMETRY = 7 + PARAM_WIDTH


def leaf_table(leaves: Leaves) -> torch.Tensor | None:
    """Every leaf's inverse map, scale and primitive geometry in one row, for fast no-grad lookups.

    Returns
    -------
    torch.Tensor or None
        ``(12, L)``: the 6 inverse-map entries, the scale and the `PARAM_WIDTH` (5) packed primitive numbers
        of each leaf id, then (affine leaves only) the 6 entries of the word's forward map: ``(18, L)``;
        None when the primitives are of several kinds (use `sdf_pairs` then). One row per quantity
        (not per leaf), so that a gather gives each quantity as a contiguous vector: the distance
        arithmetic then runs about twice as fast on CPU as on the columns of an ``(N, 12)`` gather.
    """
    if len(set(leaves.kinds)) != 1:
        return None
    leaf = torch.arange(len(leaves), device=leaves.inverse.device)
    inv, scale, forward, _, row = _gather_words(leaves, leaf)
    params = leaves.params[0].expand(len(leaf), PARAM_WIDTH) if row is None else leaves.params.index_select(0, row)
    return torch.cat([inv, scale[:, None], params] + ([] if forward is None else [forward]), 1).detach().T.contiguous()


def sdf_table(table: torch.Tensor, kind: str, x: torch.Tensor, y: torch.Tensor, leaf: torch.Tensor) -> torch.Tensor:
    """`sdf_pairs` from a `leaf_table` (one gather per pair): the same values, bit for bit, no gradient.

    Parameters
    ----------
    table : torch.Tensor
        ``(12, L)`` or ``(18, L)`` from `leaf_table`.
    kind : str
        The primitives' one kind.
    x, y, leaf : torch.Tensor
        ``(N,)`` query coordinates and leaf ids.

    Returns
    -------
    torch.Tensor
        ``(N,)``.
    """
    row = table.index_select(1, leaf)  # (12 or 18, N): each quantity contiguous
    forward = row[_GEOMETRY:].T if table.shape[0] > _GEOMETRY else None
    return leaf_sdf(kind, x, y, row[:6].T, row[6], row[7:_GEOMETRY].T, forward)


def has_slope(table: torch.Tensor | None, kind: str) -> bool:
    """Whether `sdf_table_slope` can read ``table``: one kind, with a `Shape.slope` for similarity words (no forward
    rows) or a `Shape.affine_slope` for affine ones."""
    if table is None:
        return False
    shape = SHAPES[kind]
    return (shape.slope if table.shape[0] == _GEOMETRY else shape.affine_slope) is not None


def sdf_table_slope(table: torch.Tensor, kind: str, x: torch.Tensor, y: torch.Tensor, leaf: torch.Tensor
                    ) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor, torch.Tensor]:
    """`sdf_table`'s distances, bit for bit, and their gradients in ``(x, y)``, for a table `has_slope` accepts.

    A similarity word's leaf measures ``s d(q)`` at ``q = M x + c``, so its gradient is ``s M^T`` times the
    primitive's own (`ifslib.core.geometry.shapes.Shape.slope`); an affine word's comes from the kind's
    `Shape.affine_slope`, in the plane.

    Returns
    -------
    distance, gx, gy, reach : torch.Tensor
        ``(N,)`` each, no gradient. ``reach`` is the `Shape.slope` reach in plane units: the gradient's
        direction is good to about the rounding of a coordinate divided by it.
    """
    row = table.index_select(1, leaf)
    inverse, scale = row[:6].T, row[6]
    qx, qy = _pull_back(inverse, x, y)
    if table.shape[0] > _GEOMETRY:
        return SHAPES[kind].affine_slope(x, y, qx, qy, inverse, row[_GEOMETRY:].T, scale, row[7:_GEOMETRY].T.unbind(-1))
    d, gx, gy, reach = SHAPES[kind].slope(qx, qy, row[7:_GEOMETRY])
    m0, m1, _, m3, m4, _ = row[:6]
    return scale * d, scale * (m0 * gx + m3 * gy), scale * (m1 * gx + m4 * gy), scale * reach


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
    if leaves.words_per_item:
        raise IFSError("sdf_dense takes the leaves of one IFS, not a batch")
    inv = leaves.inverse.reshape(-1, 6)
    x, y = x[:, None], y[:, None]
    per_prim = [leaf_sdf(kind, x, y, inv, leaves.scale, leaves.params[j], leaves.forward)
                for j, kind in enumerate(leaves.kinds)]
    return torch.stack(per_prim, -1).reshape(x.shape[0], -1)


__all__ = ["has_slope", "leaf_sdf", "leaf_table", "sdf_dense", "sdf_pairs", "sdf_table", "sdf_table_slope"]
