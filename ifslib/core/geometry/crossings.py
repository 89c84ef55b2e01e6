"""Self-crossings of a curve: its depth-K segments, and a differentiable penalty on their crossings."""
from __future__ import annotations

import torch

from ...errors import IFSError
from .ifs import IFS, check_depth
from .leaves import compose_words


def is_curve(ifs: IFS) -> bool:
    """Whether the rules replace one segment by a chain of segments, as the Koch curve's do: every rule a
    ``segment`` rule of one source ``(a, b)``, their targets in order a chain from ``a`` to ``b``."""
    rules = ifs.rules
    if not rules or any(r.kind != "segment" or r.source != rules[0].source for r in rules):
        return False
    chain = [rules[0].target[0]] + [r.target[1] for r in rules]
    joined = all(rules[i].target[1] == rules[i + 1].target[0] for i in range(len(rules) - 1))
    return joined and chain[0] == rules[0].source[0] and chain[-1] == rules[0].source[1]


def check_curve(ifs: IFS, what: str) -> None:
    """Raise `IFSError` saying that ``what`` needs a curve, unless every primitive is a segment."""
    if any(p.kind != "segment" for p in ifs.primitives):
        raise IFSError(f"{what} needs a curve: all primitives must be segments")


def leaf_segments(ifs: IFS, depth: int | None = None) -> torch.Tensor:
    """The depth-K copies of a curve's segment primitives, differentiable in ``ifs.points``.

    Parameters
    ----------
    ifs : IFS
        Every primitive must be a segment (its radius is ignored).
    depth : int, optional
        ``ifs.depth`` when None.

    Returns
    -------
    torch.Tensor
        ``(W * p, 2, 2)``: start and end point of each leaf segment, words in lexicographic order
        and the primitive fastest, in the dtype of ``ifs.points``.
    """
    check_curve(ifs, "a self-crossing count or penalty")
    depth = ifs.depth if depth is None else check_depth(depth)
    points = ifs.points
    words = compose_words(ifs.maps(), depth)                                      # (W, 3, 3)
    ends = torch.stack([points[list(p.points)] for p in ifs.primitives])          # (p, 2, 2)
    moved = torch.einsum("wij,pkj->wpki", words[:, :2, :2], ends) + words[:, None, None, :2, 2]
    return moved.reshape(-1, 2, 2)


def _cross(p: torch.Tensor, q: torch.Tensor, r: torch.Tensor) -> torch.Tensor:
    """z-component of ``(q - p) x (r - p)``, broadcast over leading dimensions."""
    return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])


def crossing_pairs(segments: torch.Tensor, tol: float = 1e-9
                   ) -> tuple[torch.Tensor, torch.Tensor, tuple[torch.Tensor, ...]]:
    """The pairs of segments that properly cross: each one's endpoints strictly on opposite sides of the other's line.

    Parameters
    ----------
    segments : torch.Tensor
        ``(S, 2, 2)`` start and end points.
    tol : float
        Cross products within this (times the squared extent) count as collinear, so segments that
        only touch, as consecutive pieces of a curve do, or overlap on one line never count as crossing.

    Returns
    -------
    i, j : torch.Tensor
        ``(k,)`` the crossing pairs ``i < j``, in row-major order.
    sides : tuple of torch.Tensor
        ``(S, S)`` each: the cross products ``AB x AC``, ``AB x AD``, ``CD x CA``, ``CD x CB`` of segment
        ``AB`` (row) and ``CD`` (column).
    """
    a, b = segments[:, None, 0], segments[:, None, 1]        # (S, 1, 2)
    c, d = segments[None, :, 0], segments[None, :, 1]        # (1, S, 2)
    tol = tol * max(1.0, float(segments.detach().abs().max())) ** 2
    abc, abd = _cross(a, b, c), _cross(a, b, d)               # (S, S): sides of C and D along AB
    cda, cdb = _cross(c, d, a), _cross(c, d, b)               # sides of A and B along CD
    hits = (abc * abd < 0) & (cda * cdb < 0)
    hits &= (abc.abs() > tol) & (abd.abs() > tol) & (cda.abs() > tol) & (cdb.abs() > tol)
    i, j = torch.triu(hits, 1).nonzero(as_tuple=True)
    return i, j, (abc, abd, cda, cdb)


def crossing_depths(segments: torch.Tensor, tol: float = 1e-9) -> torch.Tensor:
    """Depth of every proper crossing between the segments (`crossing_pairs`; see the module docstring).

    Parameters
    ----------
    segments : torch.Tensor
        ``(S, 2, 2)`` start and end points.
    tol : float
        As `crossing_pairs`'s.

    Returns
    -------
    torch.Tensor
        ``(k,)`` one depth per crossing pair ``i < j`` (plane units), differentiable.
    """
    i, j, (abc, abd, cda, cdb) = crossing_pairs(segments, tol)
    ab = (segments[i, 1] - segments[i, 0]).norm(dim=-1)
    cd = (segments[j, 1] - segments[j, 0]).norm(dim=-1)
    along_ab = torch.minimum(abc[i, j].abs(), abd[i, j].abs()) / ab
    along_cd = torch.minimum(cda[i, j].abs(), cdb[i, j].abs()) / cd
    return torch.minimum(along_ab, along_cd)


def crossing_penalty(ifs: IFS, depth: int | None = None) -> torch.Tensor:
    """Sum of the crossing depths of a curve's depth-K segments: 0 when it does not cross itself.

    Parameters
    ----------
    ifs : IFS
        A curve (every primitive a segment).
    depth : int, optional
        ``ifs.depth`` when None.

    Returns
    -------
    torch.Tensor
        A scalar in plane units, differentiable in ``ifs.points``.
    """
    return crossing_depths(leaf_segments(ifs, depth)).sum()


__all__ = ["check_curve", "leaf_segments", "crossing_pairs", "crossing_depths", "crossing_penalty"]
