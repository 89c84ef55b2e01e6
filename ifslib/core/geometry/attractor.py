"""Leaves of the attractor itself: the word tree cut per branch where the branch is finer than ε, point leaves
within ε of the attractor whatever the primitives (the proof: docs/results/attractor.md)."""
from __future__ import annotations

import math
import os
from dataclasses import dataclass

import torch

from ...errors import IFSError, LeafBudgetError, check_positive
from .ifs import check_depth
from .reach import WindowReach
from .words import DenseWords, WordTree
from .rules import singular_values

#: The name of the depth that means "the attractor itself" (instead of an integer K).
ATTRACTOR = "attractor"

#: Default tolerance ε in pixels: the field is within half a pixel of the distance to the attractor.
DEFAULT_TOLERANCE = 0.5

#: Default leaf budget (override with ``IFSLIB_MAX_LEAVES``): about 100 bytes a leaf while expanding.
DEFAULT_MAX_LEAVES = int(os.environ.get("IFSLIB_MAX_LEAVES", 4_000_000))

#: Depth of the words that tighten the invariant ball's radius (step 2 of the proof, docs/results/attractor.md).
BALL_WORDS = 4096

#: Leaves `sample_attractor` draws by default (``method="sampled"``).
DEFAULT_SAMPLES = 65536


def is_attractor(depth) -> bool:
    """Whether ``depth`` asks for the attractor (the string ``"attractor"``) rather than a depth K."""
    return isinstance(depth, str) and depth == ATTRACTOR


def check_depth_or_attractor(depth) -> int | str:
    """Return ``depth`` if it is an int >= 0 or ``"attractor"``, else raise `IFSError`."""
    if isinstance(depth, str):
        if depth != ATTRACTOR:
            raise IFSError(f"depth must be an integer >= 0 or {ATTRACTOR!r}, got {depth!r}")
        return depth
    return check_depth(depth)


def check_window(window) -> tuple[float, float, float, float]:
    """Return ``window = (x0, y0, x1, y1)`` as floats if it is a finite box with ``x1 > x0`` and ``y1 > y0``."""
    try:
        x0, y0, x1, y1 = (float(v) for v in window)
    except (TypeError, ValueError):
        raise IFSError(f"window must be four numbers (x0, y0, x1, y1), got {window!r}") from None
    if not all(math.isfinite(v) for v in (x0, y0, x1, y1)):
        raise IFSError(f"window must be finite, got {window!r}")
    if not (x1 > x0 and y1 > y0):
        raise IFSError(f"window {window!r} has zero or negative size: it needs x1 > x0 and y1 > y0")
    return x0, y0, x1, y1


def check_contractive_maps(maps: torch.Tensor, rules=None) -> torch.Tensor:
    """Raise `IFSError` unless every map's largest singular value is below 1; return those values ``(m,)``.

    Unlike a drawing at depth K, the attractor needs no inverse map, so a map with a singular
    value near 0 (it flattens the figure onto a line) is fine here.
    """
    largest = singular_values(maps.detach())[1]
    for i, s in enumerate(largest.tolist()):
        if not s < 1:
            kind = f" ({rules[i].kind})" if rules is not None else ""
            raise IFSError(f"rule {i}{kind} is not contractive: its scale is {s:.4g} >= 1, so the IFS has no "
                           "attractor to draw")
    return largest


def _compose(nodes: torch.Tensor, maps: torch.Tensor) -> torch.Tensor:
    """``(N, 2, 3)`` node maps composed with each of ``(m, 3, 3)`` maps on the right: ``(N * m, 2, 3)``."""
    return (nodes[:, None] @ maps[None]).reshape(-1, 2, 3)


def apply_maps(maps: torch.Tensor, point: torch.Tensor) -> torch.Tensor:
    """``(N, 2, 3)`` maps applied to one point ``(2,)``: ``(N, 2)``."""
    # not a matrix-vector product: its gradient would split the N rows by thread count
    return (maps[..., :2] * point).sum(-1) + maps[..., 2]


def prepare_maps(maps: torch.Tensor, rules=None) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor, float]:
    """What both cuts start from: the maps without autograd (checked to contract, naming ``rules``), their
    largest singular values ``(m,)``, and the ball of `attractor_ball` (its centre with autograd)."""
    with torch.no_grad():
        work = maps.detach()
        largest = check_contractive_maps(work, rules)
    centre, radius = attractor_ball(maps)
    return work, largest, centre, radius


def attractor_ball(maps: torch.Tensor) -> tuple[torch.Tensor, float]:
    """A centre ``c`` and a radius ``R`` with the attractor inside ``B(c, R)`` (steps 1-2 of the proof, docs/results/attractor.md).

    Parameters
    ----------
    maps : torch.Tensor
        ``(m, 3, 3)`` contracting maps (not checked here: see `check_contractive_maps`).

    Returns
    -------
    centre : torch.Tensor
        ``(2,)`` in the maps' dtype, differentiable in them: the centre of the box around the
        points ``T_w(f)`` of short words ``w`` (``f`` the first map's fixed point), so that ``R`` is
        near the attractor's own radius. Any point would do for the bound; this one keeps ``R``
        small, and its gradient keeps the field's gradient that of the field (finite differences
        agree), although its share, through ``L_w`` of norm at most ``ε / R``, is small.
    radius : float
        Computed in float64 from the centre's value.
    """
    m = maps.shape[0]
    k = max(1, int(math.log(BALL_WORDS) / math.log(max(m, 2))))
    fixed = torch.linalg.solve(torch.eye(2, dtype=maps.dtype, device=maps.device) - maps[0, :2, :2], maps[0, :2, 2])
    words = torch.eye(3, dtype=maps.dtype, device=maps.device)[None, :2]
    for _ in range(k):
        words = _compose(words, maps)
    pts = apply_maps(words, fixed)
    centre = (pts.min(0).values + pts.max(0).values) / 2
    with torch.no_grad():
        maps64, words64, c = maps.detach().double(), words.detach().double(), centre.detach().double()
        scales = singular_values(maps64)[1]
        r0 = float(((apply_maps(maps64[:, :2], c) - c).norm(dim=1) / (1 - scales)).max())
        tighter = float(((apply_maps(words64, c) - c).norm(dim=1) + singular_values(words64)[1] * r0).max())
    return centre, min(r0, tighter)


@dataclass
class AttractorLeaves:
    """Point leaves standing for an IFS's attractor within ``tolerance`` (see the module docstring).

    Attributes
    ----------
    points : torch.Tensor
        ``(L, 2)`` leaf points ``T_w(c)``, no gradient (for the nearest-leaf search).
    error : torch.Tensor
        ``(L,)`` each leaf's bound ``e_w = ||L_w|| R``: ``T_w(A)`` lies within ``e_w`` of its point.
    tree : DenseWords or WordTree
        Each leaf's word (`words` spells them all out; `leaf_points` only those it needs).
    maps : torch.Tensor
        ``(m, 3, 3)`` the rules' maps, with autograd (what `leaf_points` differentiates).
    centre : torch.Tensor
        ``(2,)`` the point ``c``, with autograd (see `attractor_ball`).
    radius : float
        ``R``: the attractor lies in ``B(c, R)``.
    tolerance : float
        ``ε`` in plane units: every ``e_w <= ε``.
    """

    points: torch.Tensor
    error: torch.Tensor
    tree: DenseWords | WordTree
    maps: torch.Tensor
    centre: torch.Tensor
    radius: float
    tolerance: float

    def __len__(self) -> int:
        return self.points.shape[0]

    @property
    def words(self) -> torch.Tensor:
        """``(L, K)`` uint8 (int16 above 255 maps): each leaf's word, padded with ``m`` (the identity) to the
        longest word's length ``K``."""
        return self.tree.all()

    @property
    def depth(self) -> int:
        """The longest word's length."""
        return self.tree.length


def _budget_error(tolerance: float, budget: int, level: int, open_nodes: int, m: int) -> LeafBudgetError:
    return LeafBudgetError(
        f"the attractor at a tolerance of {tolerance:.3g} plane units needs more than {budget:,} leaves "
        f"(at word length {level + 1}, {open_nodes:,} branches of {m} maps are still coarser than "
        f"it): raise max_leaves (or IFSLIB_MAX_LEAVES) or the tolerance, draw fewer pixels, or draw "
        f"sampled leaves of the cut (method='sampled'), as fits of overlapping copies do")


def attractor_leaves(maps: torch.Tensor, tolerance: float, window: tuple[float, float, float, float] | None = None,
                     max_leaves: int | None = None, rules=None) -> AttractorLeaves:
    """Cut the word tree of ``maps`` per branch where ``||L_w|| R <= tolerance`` (steps 3-4 of the proof, docs/results/attractor.md).

    Parameters
    ----------
    maps : torch.Tensor
        ``(m, 3, 3)`` contracting maps (checked: `check_contractive_maps`), with or without autograd.
    tolerance : float
        ``ε`` in plane units.
    window : (x0, y0, x1, y1), optional
        Only points of this box matter: branches that cannot hold the nearest point of the
        attractor to any point of it are dropped. None keeps every branch.
    max_leaves : int, optional
        The leaf budget (`DEFAULT_MAX_LEAVES` when None): the expansion stops with an `IFSError`
        as soon as it knows it would exceed it, before allocating the next level.
    rules : sequence of Rule, optional
        The rules the maps come from, named in the message of a map that does not contract.

    Returns
    -------
    AttractorLeaves
    """
    tolerance = check_positive(tolerance, "tolerance", " (plane units)")
    budget = DEFAULT_MAX_LEAVES if max_leaves is None else int(max_leaves)
    if budget < 1:
        raise IFSError(f"max_leaves must be >= 1, got {max_leaves!r}")
    if window is not None:
        window = check_window(window)
    work, _, centre_grad, radius = prepare_maps(maps, rules)
    m, dtype, device = work.shape[0], work.dtype, work.device
    with torch.no_grad():
        centre = centre_grad.detach()
        tree = WordTree(m, torch.uint8 if m < 255 else torch.int16)
        digits = torch.arange(m, dtype=tree.dtype, device=device)
        nodes = torch.eye(3, dtype=dtype, device=device)[None, :2]
        done_pts, done_err, done_level, done_node = [], [], [], []
        blocks = None if window is None else WindowReach(window, 2 * tolerance, dtype, device)
        if radius <= tolerance:  # the whole attractor is within ε of c: one leaf, the empty word
            nodes = nodes[:0]
            done_pts.append(centre[None]), done_err.append(torch.tensor([radius], dtype=dtype))
            done_level.append(torch.zeros(1, dtype=torch.long, device=device))
            done_node.append(torch.zeros(1, dtype=torch.long, device=device))
        n_leaves, level, parents = len(done_pts), 0, torch.zeros(1, dtype=torch.long, device=device)
        while nodes.shape[0]:
            # Every branch still open has error > ε, so it ends in at least m leaves: the count is known
            # to exceed the budget before the next level is allocated.
            if n_leaves + nodes.shape[0] * m > budget:
                raise _budget_error(tolerance, budget, level, nodes.shape[0], m)
            level += 1
            children = _compose(nodes, work)
            parent, digit = parents.repeat_interleave(m), digits.repeat(nodes.shape[0])
            err = singular_values(children)[1] * radius
            pts = apply_maps(children, centre)
            if blocks is not None:
                blocks.update(pts, err)
                keep = blocks.keep(pts, err).nonzero().flatten()
                children, parent, digit, err, pts = children[keep], parent[keep], digit[keep], err[keep], pts[keep]
            tree.parents.append(parent), tree.digits.append(digit)
            leaf = err <= tolerance
            if leaf.any():
                ids = leaf.nonzero().flatten()
                done_pts.append(pts[ids]), done_err.append(err[ids]), done_node.append(ids)
                done_level.append(torch.full_like(ids, level))
                n_leaves += ids.numel()
            parents = (~leaf).nonzero().flatten()
            nodes = children[parents]
        tree.level, tree.node = torch.cat(done_level), torch.cat(done_node)
        tree.longest = int(tree.level.max())
        points, error = torch.cat(done_pts), torch.cat(done_err)
        if blocks is not None:  # the final bounds drop the early leaves that cannot win in the window
            keep = blocks.keep(points, error).nonzero().flatten()
            points, error, tree = points[keep], error[keep], tree.subset(keep)
    return AttractorLeaves(points, error, tree, maps, centre_grad, radius, float(tolerance))


def word_maps(maps: torch.Tensor, words: torch.Tensor) -> torch.Tensor:
    """The maps ``T_w`` ``(N, 2, 3)`` of words ``(N, K)`` (padded with ``m``, the identity), from ``(m, 3, 3)`` maps."""
    eye = torch.eye(3, dtype=maps.dtype, device=maps.device)[None]
    table = torch.cat([maps, eye])  # word digit m is the identity (padding)
    digits = words.long()
    if digits.shape[1] == 0:
        return eye[:, :2].expand(words.shape[0], 2, 3)
    composed = table.index_select(0, digits[:, 0])[:, :2]
    for j in range(1, digits.shape[1]):
        composed = composed @ table.index_select(0, digits[:, j])
    return composed


def leaf_points(leaves: AttractorLeaves, index: torch.Tensor) -> torch.Tensor:
    """The points ``T_w(c)`` of the leaves ``index`` (``(N,)`` ids), recomputed with autograd through the maps.

    Returns
    -------
    torch.Tensor
        ``(N, 2)``: the same values as ``leaves.points[index]`` (up to rounding), differentiable
        in the control points the maps were built from.
    """
    digits = leaves.tree.select(index)
    if digits.shape[1] == 0:
        return leaves.centre.expand(index.numel(), 2)
    return apply_maps(word_maps(leaves.maps, digits), leaves.centre)


__all__ = ["ATTRACTOR", "AttractorLeaves", "DEFAULT_SAMPLES", "DEFAULT_TOLERANCE", "DEFAULT_MAX_LEAVES",
           "attractor_ball", "attractor_leaves", "check_contractive_maps", "check_depth_or_attractor",
           "check_window", "is_attractor", "leaf_points"]
