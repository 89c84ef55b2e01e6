"""Leaves of the attractor itself: the word tree cut per branch where the branch is finer than ε.

A drawing at depth K is ``H^K(primitives)``; what the inverse problem asks for is the attractor
``A = H(A)``, which does not depend on the primitives. This module makes *point* leaves that stand
for ``A`` within a stated tolerance ``ε`` (plane units), whatever the primitives: a branch of scale
0.85 is cut much deeper than one of 0.2, and a map with a singular value near 0 (a fern's stem)
needs no inverse.

The bound, and why it holds
---------------------------
Let every map ``T_i(x) = L_i x + t_i`` contract (``s_i = ||L_i||_2 < 1``); write ``T_w`` for the
composition ``T_{w_1} o ... o T_{w_k}`` of a word ``w``, and let ``c`` be any point.

1. *An invariant ball.* With ``R0 = max_i |T_i(c) - c| / (1 - s_i)``, each ``T_i`` maps the ball
   ``B0 = B(c, R0)`` into itself: ``|T_i(x) - c| <= s_i |x - c| + |T_i(c) - c| <= s_i R0 + (1 - s_i) R0``.
   So ``H(B0) ⊂ B0`` and ``A``, the limit of ``H^k(B0)``, lies in ``B0``.
2. *A tighter radius.* ``A = H^k(A) ⊂ ∪_{|w| = k} T_w(B0)`` and ``T_w(B0) ⊂ B(T_w(c), ||L_w|| R0)``, so every
   point of ``A`` lies within ``R = max_{|w| = k} (|T_w(c) - c| + ||L_w|| R0)`` of ``c`` (`attractor_ball`).
3. *Leaves.* Cut every branch of the word tree once, at a word ``w`` with ``e_w = ||L_w|| R <= ε``
   (the cut words form a cover: every infinite word has exactly one prefix among them), and take
   the leaf point ``p_w = T_w(c)``. Then ``A = ∪_w T_w(A)`` and ``T_w(A) ⊂ B(p_w, e_w)``: every point
   of ``A`` is within ``ε`` of a leaf, and every leaf is within ``ε`` of a point of ``A``. Hence, for
   every ``x`` in the plane::

       d(x, A) - ε  <=  d(x, leaves)  <=  d(x, A) + ε.

   ``||L_w||`` is the composed matrix's own largest singular value (not the product of the
   rules' scales, which can be far larger for shears and rotations).
4. *A window.* When only the pixels of a window matter: ``d(., A)`` is 1-Lipschitz, so every
   window point has ``d(x, A) <= U = min_w (|m - p_w| + e_w) + h`` (``m`` the window's centre, ``h``
   its half-diagonal, the minimum over the current cover). A node whose ball ``B(p_w, e_w)`` lies
   farther than ``U`` from the window holds no window point's nearest point of ``A``, so its branch
   is dropped and the bound of 3 still holds at every point of the window. This is what lets a
   64x zoom refine only the leaves near the window.

The expansion runs with no autograd and keeps each leaf's word (`AttractorLeaves.words`);
`leaf_points` recomputes the points of the few leaves that win some pixel with autograd, so the
gradient is exact (that of ``|x - T_w(c)|`` through the winner) and memory is O(pixels + leaves).
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass

import torch

from ..errors import IFSError, LeafBudgetError, check_positive
from .ifs import IFS, check_depth
from .rules import rule_maps, singular_values

#: The name of the depth that means "the attractor itself" (instead of an integer K).
ATTRACTOR = "attractor"

#: Default tolerance ε in pixels: the field is within half a pixel of the distance to the attractor.
DEFAULT_TOLERANCE = 0.5

#: Default leaf budget (override with ``IFSLIB_MAX_LEAVES``): about 100 bytes a leaf while expanding.
DEFAULT_MAX_LEAVES = int(os.environ.get("IFSLIB_MAX_LEAVES", 4_000_000))

#: Depth of the words that tighten the invariant ball's radius (step 2 of the module docstring).
BALL_WORDS = 4096

#: The chaos game (`ifslib.raster.chaos`) and `sample_attractor` choose map ``i`` in proportion to
#: ``max(|det L_i|, CHAOS_FLOOR * max_j |det L_j|)`` (`chaos_probabilities`).
CHAOS_FLOOR = 0.02

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


def check_tolerance(tolerance) -> float:
    """Return ``tolerance`` (pixels) as a float if it is finite and > 0, else raise `IFSError`."""
    return check_positive(tolerance, "tolerance", " of pixels")


def _plane_tolerance(tolerance) -> float:
    """``tolerance`` (plane units) as a float, if it is a finite real number > 0; else `IFSError`."""
    return check_positive(tolerance, "tolerance", " (plane units)")


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


def _apply(maps: torch.Tensor, point: torch.Tensor) -> torch.Tensor:
    """``(N, 2, 3)`` maps applied to one point ``(2,)``: ``(N, 2)``."""
    # a product and a sum over the last axis, not a matrix-vector product: the point's gradient is
    # then a reduction to two outputs, each in one thread, where mv's splits the N rows by thread count
    return (maps[..., :2] * point).sum(-1) + maps[..., 2]


def chaos_probabilities(maps: torch.Tensor) -> torch.Tensor:
    """The chaos game's choice of maps: ``(..., m)`` float64 probabilities for ``(..., m, 3, 3)`` (or ``(..., m, 2, 3)``) maps.

    In proportion to the area each map keeps, ``|det L_i|``, with a floor of `CHAOS_FLOOR` times the
    largest, so that a map that flattens the figure (a fern's stem) is still chosen. Leading
    dimensions are a batch of IFSs, each normalised on its own.
    """
    lin = maps.detach()[..., :2, :2]
    det = (lin[..., 0, 0] * lin[..., 1, 1] - lin[..., 0, 1] * lin[..., 1, 0]).abs().double()
    weight = torch.maximum(det, CHAOS_FLOOR * det.amax(-1, keepdim=True).clamp_min(1e-300))
    return weight / weight.sum(-1, keepdim=True)


def _prepare(maps: torch.Tensor, rules=None) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor, float]:
    """What both cuts start from: the maps without autograd (checked to contract, naming ``rules``), their
    largest singular values ``(m,)``, and the ball of `attractor_ball` (its centre with autograd)."""
    with torch.no_grad():
        work = maps.detach()
        largest = check_contractive_maps(work, rules)
    centre, radius = attractor_ball(maps)
    return work, largest, centre, radius


def attractor_ball(maps: torch.Tensor) -> tuple[torch.Tensor, float]:
    """A centre ``c`` and a radius ``R`` with the attractor inside ``B(c, R)`` (steps 1-2 of the module docstring).

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
    pts = _apply(words, fixed)
    centre = (pts.min(0).values + pts.max(0).values) / 2
    with torch.no_grad():
        maps64, words64, c = maps.detach().double(), words.detach().double(), centre.detach().double()
        scales = singular_values(maps64)[1]
        r0 = float(((_apply(maps64[:, :2], c) - c).norm(dim=1) / (1 - scales)).max())
        tighter = float(((_apply(words64, c) - c).norm(dim=1) + singular_values(words64)[1] * r0).max())
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
    words : torch.Tensor
        ``(L, K)`` uint8 (int16 above 255 maps): each leaf's word, padded with ``m`` (the identity)
        to the longest word's length ``K``.
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
    words: torch.Tensor
    maps: torch.Tensor
    centre: torch.Tensor
    radius: float
    tolerance: float

    def __len__(self) -> int:
        return self.points.shape[0]

    @property
    def depth(self) -> int:
        """The longest word's length."""
        return self.words.shape[1]


def _to_window(points: torch.Tensor, window: tuple[float, float, float, float]) -> torch.Tensor:
    """Distance from each of ``(N, 2)`` points to the box ``window`` (0 inside): ``(N,)``."""
    x0, y0, x1, y1 = window
    dx = torch.clamp(torch.maximum(x0 - points[:, 0], points[:, 0] - x1), min=0)
    dy = torch.clamp(torch.maximum(y0 - points[:, 1], points[:, 1] - y1), min=0)
    return torch.hypot(dx, dy)


def attractor_leaves(maps: torch.Tensor, tolerance: float, window: tuple[float, float, float, float] | None = None,
                     max_leaves: int | None = None, rules=None) -> AttractorLeaves:
    """Cut the word tree of ``maps`` per branch where ``||L_w|| R <= tolerance`` (steps 3-4 of the module docstring).

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
    tolerance = _plane_tolerance(tolerance)
    budget = DEFAULT_MAX_LEAVES if max_leaves is None else int(max_leaves)
    if budget < 1:
        raise IFSError(f"max_leaves must be >= 1, got {max_leaves!r}")
    if window is not None:
        window = check_window(window)
    work, _, centre_grad, radius = _prepare(maps, rules)
    m, dtype = work.shape[0], work.dtype
    with torch.no_grad():
        centre = centre_grad.detach()
        word_dtype = torch.uint8 if m < 255 else torch.int16
        nodes = torch.eye(3, dtype=dtype, device=work.device)[None, :2]
        words = torch.empty((1, 0), dtype=word_dtype, device=work.device)
        digits = torch.arange(m, dtype=word_dtype, device=work.device)
        done_pts, done_err, done_words = [], [], []
        n_leaves = 0
        if window is not None:
            mid = torch.tensor([(window[0] + window[2]) / 2, (window[1] + window[3]) / 2], dtype=dtype,
                               device=work.device)
            half = math.hypot(window[2] - window[0], window[3] - window[1]) / 2
            reach = math.inf  # U - h: the smallest |mid - p_w| + e_w seen so far
        if radius <= tolerance:  # the whole attractor is within ε of c
            nodes = nodes[:0]
            done_pts.append(centre[None]), done_err.append(torch.tensor([radius], dtype=dtype)), done_words.append(words)
            n_leaves = 1
        level = 0
        while nodes.shape[0]:
            # Every branch still open has error > ε, so it ends in at least m leaves: the count is known
            # to exceed the budget before the next level is allocated.
            if n_leaves + nodes.shape[0] * m > budget:
                raise LeafBudgetError(
                    f"the attractor at a tolerance of {tolerance:.3g} plane units needs more than {budget:,} leaves "
                    f"(at word length {level + 1}, {nodes.shape[0]:,} branches of {m} maps are still coarser than "
                    f"it): raise max_leaves (or IFSLIB_MAX_LEAVES) or the tolerance, draw fewer pixels, or draw "
                    f"sampled leaves of the cut (method='sampled'), as fits of overlapping copies do")
            level += 1
            children = _compose(nodes, work)
            words = torch.cat([words.repeat_interleave(m, 0), digits.repeat(nodes.shape[0])[:, None]], 1)
            err = singular_values(children)[1] * radius
            pts = _apply(children, centre)
            if window is not None:
                reach = min(reach, float(((pts - mid).norm(dim=1) + err).min()))
                keep = (_to_window(pts, window) - err <= reach + half).nonzero().flatten()
                children, words, err, pts = children[keep], words[keep], err[keep], pts[keep]
            leaf = err <= tolerance
            if leaf.any():
                done_pts.append(pts[leaf]), done_err.append(err[leaf]), done_words.append(words[leaf])
                n_leaves += int(leaf.sum())
            open_ = ~leaf
            nodes, words = children[open_], words[open_]
        depth = max(w.shape[1] for w in done_words)
        words = torch.cat([torch.nn.functional.pad(w, (0, depth - w.shape[1]), value=m) for w in done_words])
        points, error = torch.cat(done_pts), torch.cat(done_err)
        if window is not None:  # the final reach drops the early leaves that cannot win in the window
            keep = (_to_window(points, window) - error <= reach + half).nonzero().flatten()
            points, error, words = points[keep], error[keep], words[keep]
    return AttractorLeaves(points, error, words, maps, centre_grad, radius, float(tolerance))


def expand_attractor(ifs: IFS, tolerance: float, window: tuple[float, float, float, float] | None = None, *,
                     max_leaves: int | None = None, device: torch.device | str = "cpu",
                     dtype: torch.dtype | None = None, gradient: str = "exact",
                     samples: int | None = None) -> AttractorLeaves:
    """The attractor's point leaves of an IFS (see `attractor_leaves`), differentiable through `leaf_points`.

    Parameters
    ----------
    ifs : IFS
        Its rules must contract (largest singular value < 1); its primitives play no part.
    tolerance : float
        ``ε`` in plane units.
    window : (x0, y0, x1, y1), optional
        The box whose points matter (see `attractor_leaves`).
    max_leaves : int, optional
        Leaf budget; `DEFAULT_MAX_LEAVES` when None.
    device, dtype, gradient
        As in `ifslib.geometry.leaves.expand`.
    samples : int, optional
        Draw this many leaves of the cut at random (`sample_attractor`) instead of the whole cut
        (then ``window`` and ``max_leaves`` play no part).

    Returns
    -------
    AttractorLeaves
    """
    ifs.validate()
    points = ifs.points.to(device=device, dtype=dtype or ifs.points.dtype)
    maps = rule_maps(points, ifs.rules, gradient)
    if samples is not None:
        return sample_attractor(maps, tolerance, samples, rules=ifs.rules)
    return attractor_leaves(maps, tolerance, window, max_leaves, ifs.rules)


_UNIFORMS: dict = {}
#: `sample_attractor` refuses maps whose walkers would need longer words than this (a scale near 1:
#: ``n`` walkers keep ``n`` uniforms per letter).
MAX_WORD_LENGTH = 512


def _uniforms(seed: int, n: int, cols: int) -> torch.Tensor:
    """``(n, cols)`` float64 uniforms, the same for the same ``(seed, n)`` whatever was asked before.

    Cached (a fit asks every step), and drawn column by column (walker ``i``'s uniform for letter ``j`` is the
    generator's number ``j * n + i``), so a cache grown for longer words keeps the columns it had: drawn row by row,
    growing it changed every uniform, and a fit's sampled leaves depended on the fits run before it in the process.
    """
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


def sample_attractor(maps: torch.Tensor, tolerance: float, n: int, seed: int = 0, rules=None) -> AttractorLeaves:
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

    Returns
    -------
    AttractorLeaves
    """
    tolerance = _plane_tolerance(tolerance)
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise IFSError(f"the number of sampled leaves must be an integer >= 1, got {n!r}")
    work, largest, centre_grad, radius = _prepare(maps, rules)
    m, dtype, device = work.shape[0], work.dtype, work.device
    with torch.no_grad():
        centre = centre_grad.detach()
        # the deepest a walker can go: every step shrinks its error by at least the largest scale
        longest = max(1, math.ceil(math.log(tolerance / radius) / math.log(float(largest.max())))) if radius > tolerance else 0
        if longest > MAX_WORD_LENGTH:
            raise IFSError(f"a map contracts too slowly (largest scale {float(largest.max()):.6f}): sampled leaves would "
                           f"need words of {longest} maps, more than {MAX_WORD_LENGTH}")
        # inverse-CDF draws from fixed uniforms: the same seed gives the same words while the maps move
        cdf = chaos_probabilities(work).cumsum(0)
        digits = torch.searchsorted(cdf[:-1].contiguous(), _uniforms(int(seed), n, max(longest, 1)).contiguous()).to(device)
        word_dtype = torch.uint8 if m < 255 else torch.int16
        current = torch.eye(3, dtype=dtype, device=device)[None, :2].repeat(n, 1, 1)
        length = torch.zeros(n, dtype=torch.long, device=device)
        active = torch.full((n,), radius > tolerance, dtype=torch.bool, device=device)
        error = torch.full((n,), radius, dtype=dtype, device=device)
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
        words = torch.where(steps[None] < length[:, None], digits[:, :depth], m).to(word_dtype)
        points = _apply(current, centre)
    return AttractorLeaves(points, error, words, maps, centre_grad, radius, float(tolerance))


def leaf_points(leaves: AttractorLeaves, index: torch.Tensor) -> torch.Tensor:
    """The points ``T_w(c)`` of the leaves ``index`` (``(N,)`` ids), recomputed with autograd through the maps.

    Returns
    -------
    torch.Tensor
        ``(N, 2)``: the same values as ``leaves.points[index]`` (up to rounding), differentiable
        in the control points the maps were built from.
    """
    maps = leaves.maps
    eye = torch.eye(3, dtype=maps.dtype, device=maps.device)[None]
    table = torch.cat([maps, eye])  # word digit m is the identity (padding)
    digits = leaves.words.index_select(0, index).long()
    if digits.shape[1] == 0:
        return leaves.centre.expand(index.numel(), 2)
    composed = table.index_select(0, digits[:, 0])[:, :2]
    for j in range(1, digits.shape[1]):
        composed = composed @ table.index_select(0, digits[:, j])
    return _apply(composed, leaves.centre)


__all__ = ["ATTRACTOR", "AttractorLeaves", "CHAOS_FLOOR", "chaos_probabilities", "DEFAULT_SAMPLES", "DEFAULT_TOLERANCE", "DEFAULT_MAX_LEAVES",
           "attractor_ball", "attractor_leaves", "check_contractive_maps", "check_depth_or_attractor",
           "check_tolerance", "check_window", "expand_attractor", "is_attractor", "leaf_points", "sample_attractor"]
