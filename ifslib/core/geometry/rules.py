"""Symmetry rules: each kind builds one differentiable 3 x 3 map from the control points (docs/guide/conventions.md)."""
from __future__ import annotations

from dataclasses import dataclass

import torch

from ...errors import IFSError

RULE_KINDS = ("segment", "square", "affine")
#: Control points on each side of a rule, by kind.
RULE_POINTS = {"segment": 2, "square": 2, "affine": 3}
GRADIENT_MODES = ("exact", "paper")

#: Below this length a rule's source segment or diagonal (or the square root of twice an affine
#: rule's source triangle's area) counts as zero (plane units).
MIN_LENGTH = 1e-9
#: A map whose smallest singular value is below this is degenerate: its inverse (every leaf's distance) blows up.
MIN_SINGULAR = 1e-6


@dataclass(frozen=True)
class Rule:
    """One symmetry rule: map the control points ``source`` onto ``target`` (docs/guide/conventions.md, "Rules"):
    two indices each for a ``segment`` (endpoints) or a ``square`` (diagonal corners), three for an ``affine`` rule."""

    kind: str
    source: tuple[int, ...]
    target: tuple[int, ...]

    def __post_init__(self) -> None:
        if self.kind not in RULE_KINDS:
            raise IFSError(f"unknown rule kind {self.kind!r}; known kinds: {', '.join(RULE_KINDS)}")
        need = RULE_POINTS[self.kind]
        for name in ("source", "target"):
            value = tuple(getattr(self, name))
            if len(value) != need or not all(isinstance(i, int) and not isinstance(i, bool) for i in value):
                article = "an" if self.kind[0] in "aeiou" else "a"
                field = {"source": "from", "target": "to"}[name]  # as in the JSON file
                raise IFSError(f"{article} {self.kind} rule's {field!r} must be {need} point indices, got {list(value)!r}")
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


def _det2(u: torch.Tensor, v: torch.Tensor) -> torch.Tensor:
    """``det [u, v]`` of column pairs ``(..., 2)``."""
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def _affine_coefficients(points: torch.Tensor, rules: list[Rule]) -> tuple[torch.Tensor, torch.Tensor]:
    """Matrix ``(..., k, 2, 2)`` and translation ``(..., k, 2)`` of the affine rules (triangle onto triangle)."""
    idx = torch.tensor([r.source + r.target for r in rules], device=points.device)
    pa, pb, pc, pd, pe, pf = (points[..., idx[:, j], :] for j in range(6))
    u, v = pb - pa, pc - pa          # source edges: S = [u, v] (columns)
    det = _det2(u, v)
    # S^-1 = [[v_y, -v_x], [-u_y, u_x]] / det; A = [e - d, f - d] S^-1, written out entry by entry
    eu, ev = pe - pd, pf - pd
    a = (eu[..., 0] * v[..., 1] - ev[..., 0] * u[..., 1]) / det
    b = (ev[..., 0] * u[..., 0] - eu[..., 0] * v[..., 0]) / det
    c = (eu[..., 1] * v[..., 1] - ev[..., 1] * u[..., 1]) / det
    d = (ev[..., 1] * u[..., 0] - eu[..., 1] * v[..., 0]) / det
    matrix = torch.stack([torch.stack([a, b], -1), torch.stack([c, d], -1)], -2)
    return matrix, pd - (matrix @ pa[..., None])[..., 0]


def rule_lengths(points: torch.Tensor, rules: list[Rule]) -> torch.Tensor:
    """How far each rule's source is from degenerate, ``(..., m)`` (no gradient): a segment's or diagonal's length,
    for an affine rule ``sqrt(|det [p_b - p_a, p_c - p_a]|)``."""
    pts = points.detach()
    out = []
    for rule in rules:
        pa, pb = pts[..., rule.source[0], :], pts[..., rule.source[1], :]
        if rule.kind == "affine":
            out.append(_det2(pb - pa, pts[..., rule.source[2], :] - pa).abs().sqrt())
        else:
            out.append((pb - pa).norm(dim=-1))
    return torch.stack(out, -1)


def check_rule_lengths(points: torch.Tensor, rules: list[Rule]) -> None:
    """Raise `IFSError` if a rule's source segment or diagonal has zero length (an affine rule's triangle zero area)."""
    for i, (rule, length) in enumerate(zip(rules, rule_lengths(points, rules).tolist())):
        if not length > MIN_LENGTH:
            if rule.kind == "affine":
                what = f"triangle on points {list(rule.source)} has zero area"
            else:
                a, b = rule.source
                what = f"{'segment' if rule.kind == 'segment' else 'diagonal'} from point {a} to point {b} has zero length"
            raise IFSError(f"rule {i} ({rule.kind}): its source {what} ({length:.3g}), so no map is defined")


def rule_maps(points: torch.Tensor, rules: list[Rule], gradient: str = "exact") -> torch.Tensor:
    """The rules' ``(m, 3, 3)`` maps from control points ``(n, 2)`` (any leading batch shape), differentiable; a
    batch is not checked here (its caller checks each item with `rule_lengths`)."""
    check_gradient_mode(gradient)
    if points.ndim == 2:
        check_rule_lengths(points, rules)
    batch, m = points.shape[:-2], len(rules)
    seg = [i for i, r in enumerate(rules) if r.kind == "segment"]
    sq = [i for i, r in enumerate(rules) if r.kind == "square"]
    af = [i for i, r in enumerate(rules) if r.kind == "affine"]
    parts = []
    if seg:
        alpha, beta = _segment_coefficients(points, [rules[i] for i in seg], gradient)
        parts.append(torch.stack([alpha[..., 0], -alpha[..., 1], beta[..., 0],
                                  alpha[..., 1], alpha[..., 0], beta[..., 1]], -1))
    if sq:
        scale, t = _square_coefficients(points, [rules[i] for i in sq])
        zero = torch.zeros_like(scale)
        parts.append(torch.stack([scale, zero, t[..., 0], zero, scale, t[..., 1]], -1))
    if af:
        matrix, t = _affine_coefficients(points, [rules[i] for i in af])
        parts.append(torch.cat([matrix, t[..., None]], -1).flatten(-2))
    top = torch.cat(parts, -2)  # (..., m, 6), segment rules first, then square, then affine
    order = seg + sq + af
    if order != list(range(m)):
        top = top[..., torch.tensor([order.index(i) for i in range(m)], device=points.device), :]
    bottom = torch.tensor([0.0, 0.0, 1.0], dtype=points.dtype, device=points.device).expand(*batch, m, 1, 3)
    return torch.cat([top.reshape(*batch, m, 2, 3), bottom], dim=-2)


def map_scales(maps: torch.Tensor) -> torch.Tensor:
    """Scale of each similarity map, ``sqrt(|det A|)`` (for a general affine map use `singular_values`)."""
    a = maps[..., :2, :2]
    det = a[..., 0, 0] * a[..., 1, 1] - a[..., 0, 1] * a[..., 1, 0]
    return det.abs().sqrt()


def singular_values(maps: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """Smallest and largest singular values of each map's 2 x 2 matrix in closed form, from the norms of
    ``(a + d, b - c)`` and ``(a - d, b + c)``, clamped so the gradient stays finite where they vanish."""
    a, b, c, d = maps[..., 0, 0], maps[..., 0, 1], maps[..., 1, 0], maps[..., 1, 1]
    tiny = torch.finfo(maps.dtype).tiny
    n1 = ((a + d) ** 2 + (b - c) ** 2).clamp_min(tiny).sqrt()
    n2 = ((a - d) ** 2 + (b + c) ** 2).clamp_min(tiny).sqrt()
    return (n1 - n2).abs() / 2, (n1 + n2) / 2


#: The chaos game (`ifslib.core.raster.chaos`) and `sample_attractor` choose map ``i`` in proportion to
#: ``max(|det L_i|, CHAOS_FLOOR * max_j |det L_j|)`` (`chaos_probabilities`).
CHAOS_FLOOR = 0.02


def chaos_probabilities(maps: torch.Tensor) -> torch.Tensor:
    """The chaos game's choice of maps, ``(..., m)`` float64: in proportion to ``|det L_i|`` with a floor of
    `CHAOS_FLOOR` times the largest, so a flattening map (a fern's stem) is still chosen."""
    lin = maps.detach()[..., :2, :2]
    det = (lin[..., 0, 0] * lin[..., 1, 1] - lin[..., 0, 1] * lin[..., 1, 0]).abs().double()
    weight = torch.maximum(det, CHAOS_FLOOR * det.amax(-1, keepdim=True).clamp_min(1e-300))
    return weight / weight.sum(-1, keepdim=True)
