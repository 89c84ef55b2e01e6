"""Symmetry rules: each rule kind builds one differentiable map T_i from the control points.

A rule ``(P_i, R_i)`` names control points by index; its map is a 3 x 3 homogeneous matrix
``[[a, b, tx], [c, d, ty], [0, 0, 1]]`` acting on column vectors ``(x, y, 1)``
(see ``CONVENTIONS.md``).

Kinds
-----
``segment``
    The similarity (rotation + uniform scale + translation, no reflection) taking the segment
    ``p_a -> p_b`` onto ``p_c -> p_d``. In complex numbers it is ``z -> alpha z + beta`` with
    ``alpha = (p_d - p_c) / (p_b - p_a)`` and ``beta = p_c - alpha p_a``: every entry is a rational
    function of the points, so autograd gives the exact gradient, rotation included.
``square``
    Uniform scale + translation taking the axis-aligned square with diagonal corners ``P_i`` onto
    the one with diagonal corners ``R_i``: scale = ratio of the diagonals' lengths, lower-left corner
    to lower-left corner.

Gradient modes
--------------
``"exact"`` (default) differentiates everything. ``"paper"`` reproduces the code published with the
paper, which rebuilt each segment rule's rotation with ``torch.tensor([...])`` and so cut its
gradient: the rotation's value is used, but no gradient flows through it, while scale and
translation keep theirs. Square rules have no rotation and are the same in both modes.
"""
from __future__ import annotations

from dataclasses import dataclass

import torch

from ..errors import IFSError

RULE_KINDS = ("segment", "square")
GRADIENT_MODES = ("exact", "paper")

#: Below this length a rule's source segment or diagonal counts as zero (plane units).
MIN_LENGTH = 1e-9


@dataclass(frozen=True)
class Rule:
    """One symmetry rule: map the control points ``source`` onto ``target``.

    Parameters
    ----------
    kind : {"segment", "square"}
        How the two point pairs define the map (see the module docstring).
    source, target : tuple of int
        Two control-point indices each: segment endpoints, or diagonal corners of a square.
    """

    kind: str
    source: tuple[int, int]
    target: tuple[int, int]

    def __post_init__(self) -> None:
        if self.kind not in RULE_KINDS:
            raise IFSError(f"unknown rule kind {self.kind!r}; known kinds: {', '.join(RULE_KINDS)}")
        for name in ("source", "target"):
            value = tuple(getattr(self, name))
            if len(value) != 2 or not all(isinstance(i, int) and not isinstance(i, bool) for i in value):
                raise IFSError(f"a {self.kind} rule's {name!r} must be two point indices, got {value!r}")
            object.__setattr__(self, name, value)


def check_gradient_mode(gradient: str) -> str:
    """Return ``gradient`` if it is a known mode, else raise `IFSError`."""
    if gradient not in GRADIENT_MODES:
        raise IFSError(f"unknown gradient mode {gradient!r}; known modes: {', '.join(GRADIENT_MODES)}")
    return gradient


def _segment_coefficients(points: torch.Tensor, rules: list[Rule], gradient: str) -> tuple[torch.Tensor, torch.Tensor]:
    """Complex coefficients (alpha, beta) of the segment rules, as real pairs: (..., k, 2) and (..., k, 2)."""
    idx = torch.tensor([r.source + r.target for r in rules], device=points.device)
    pa, pb, pc, pd = (points[..., idx[:, j], :] for j in range(4))
    u, v = pb - pa, pd - pc
    uu = (u * u).sum(-1)
    # alpha = v / u = v * conj(u) / |u|^2
    alpha = torch.stack([(v[..., 0] * u[..., 0] + v[..., 1] * u[..., 1]) / uu,
                         (v[..., 1] * u[..., 0] - v[..., 0] * u[..., 1]) / uu], -1)
    if gradient == "paper":
        # The paper's code: the rotation is a constant, the scale |v| / |u| keeps its gradient.
        scale = torch.sqrt((v * v).sum(-1) / uu)
        rotation = alpha.detach() / alpha.detach().norm(dim=-1, keepdim=True)
        alpha = scale[..., None] * rotation
    beta = pc - torch.stack([alpha[..., 0] * pa[..., 0] - alpha[..., 1] * pa[..., 1],
                             alpha[..., 1] * pa[..., 0] + alpha[..., 0] * pa[..., 1]], -1)
    return alpha, beta


def _square_coefficients(points: torch.Tensor, rules: list[Rule]) -> tuple[torch.Tensor, torch.Tensor]:
    """Scale s (..., k) and translation t (..., k, 2) of the square rules."""
    idx = torch.tensor([r.source + r.target for r in rules], device=points.device)
    q1, q2, r1, r2 = (points[..., idx[:, j], :] for j in range(4))
    scale = (r2 - r1).norm(dim=-1) / (q2 - q1).norm(dim=-1)
    lower_left_p = torch.minimum(q1, q2)
    lower_left_r = torch.minimum(r1, r2)
    return scale, lower_left_r - scale[..., None] * lower_left_p


def check_rule_lengths(points: torch.Tensor, rules: list[Rule]) -> None:
    """Raise `IFSError` if a rule's source segment (or diagonal) has zero length."""
    pts = points.detach()
    for i, rule in enumerate(rules):
        a, b = rule.source
        length = float((pts[b] - pts[a]).norm())
        if not length > MIN_LENGTH:
            what = "segment" if rule.kind == "segment" else "diagonal"
            raise IFSError(f"rule {i} ({rule.kind}): its source {what} from point {a} to point {b} "
                           f"has zero length ({length:.3g}), so no map is defined")


def rule_lengths(points: torch.Tensor, rules: list[Rule]) -> torch.Tensor:
    """Length of each rule's source segment (or diagonal), ``(..., m)`` for points ``(..., n, 2)`` (no gradient)."""
    idx = torch.tensor([r.source for r in rules], device=points.device)
    pts = points.detach()
    return (pts[..., idx[:, 1], :] - pts[..., idx[:, 0], :]).norm(dim=-1)


def rule_maps(points: torch.Tensor, rules: list[Rule], gradient: str = "exact") -> torch.Tensor:
    """Build the map matrices of the rules from the control points.

    Parameters
    ----------
    points : torch.Tensor
        Control points, ``(n, 2)``, or a batch of point sets ``(B, n, 2)`` (any leading shape).
    rules : list of Rule
        The ``m`` symmetry rules.
    gradient : {"exact", "paper"}
        Gradient mode (see the module docstring).

    Returns
    -------
    torch.Tensor
        ``(m, 3, 3)`` homogeneous matrices (``(B, m, 3, 3)`` for a batch), differentiable in ``points``.

    Raises
    ------
    IFSError
        For one point set, when a rule's source has zero length. A batch is not checked here: its
        caller checks each item with `rule_lengths`.
    """
    check_gradient_mode(gradient)
    if points.ndim == 2:
        check_rule_lengths(points, rules)
    batch, m = points.shape[:-2], len(rules)
    seg = [i for i, r in enumerate(rules) if r.kind == "segment"]
    sq = [i for i, r in enumerate(rules) if r.kind == "square"]
    parts = []
    if seg:
        alpha, beta = _segment_coefficients(points, [rules[i] for i in seg], gradient)
        parts.append(torch.stack([alpha[..., 0], -alpha[..., 1], beta[..., 0],
                                  alpha[..., 1], alpha[..., 0], beta[..., 1]], -1))
    if sq:
        scale, t = _square_coefficients(points, [rules[i] for i in sq])
        zero = torch.zeros_like(scale)
        parts.append(torch.stack([scale, zero, t[..., 0], zero, scale, t[..., 1]], -1))
    top = torch.cat(parts, -2)  # (..., m, 6), segment rules first
    order = seg + sq
    if order != list(range(m)):
        top = top[..., torch.tensor([order.index(i) for i in range(m)], device=points.device), :]
    bottom = torch.tensor([0.0, 0.0, 1.0], dtype=points.dtype, device=points.device).expand(*batch, m, 1, 3)
    return torch.cat([top.reshape(*batch, m, 2, 3), bottom], dim=-2)


def map_scales(maps: torch.Tensor) -> torch.Tensor:
    """Contraction factor of each similarity map: ``sqrt(|det A|)``, shape ``(..., )`` for ``(..., 3, 3)``."""
    a = maps[..., :2, :2]
    det = a[..., 0, 0] * a[..., 1, 1] - a[..., 0, 1] * a[..., 1, 0]
    return det.abs().sqrt()
