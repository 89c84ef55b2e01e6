"""The IFS object: control points (a leaf tensor that requires grad: fitting moves them), symmetry rules,
primitives and a depth, validated."""
from __future__ import annotations

import copy
import math
from typing import Any, Iterable, Sequence

import numpy as np
import torch

from ...errors import IFSError, check_int, check_positive
from .primitives import Primitive
from .rules import MIN_SINGULAR, Rule, chaos_probabilities, check_gradient_mode, check_rule_lengths, rule_maps, singular_values


def _as_rule(rule: Rule | dict) -> Rule:
    if isinstance(rule, Rule):
        return rule
    return Rule(rule["kind"], tuple(rule["from"]), tuple(rule["to"]))


def _as_primitive(prim: Primitive | dict) -> Primitive:
    if isinstance(prim, Primitive):
        return prim
    return Primitive(prim["kind"], tuple(prim["points"]), prim.get("radius", 0.0))


class IFS:
    """An iterated function system defined on control points.

    Parameters
    ----------
    points : array-like
        Control points, ``(n, 2)``, in plane units (the image plane is ``[-0.5, 0.5]^2``).
    rules : sequence of Rule (or dicts with ``kind``, ``from``, ``to``)
        The ``m`` symmetry rules; each makes one map.
    primitives : sequence of Primitive (or dicts with ``kind``, ``points``, ``radius``)
        The shapes drawn at the leaves.
    depth : int
        Number of Hutchinson steps ``K`` (0 draws the primitives as they are).
    name : str
        A label, saved in the JSON file.
    fixed : iterable of int
        Indices of control points that fitting must not move.
    sigma : float, optional
        Rendering width in plane units; `ifslib.render` uses it when given no ``sigma``.
    meta : dict, optional
        Free-form metadata (a fit's history, say), saved in the JSON file.
    dtype : torch.dtype
        Floating type of ``points`` (float32 by default; float64 on request).
    probabilities : sequence of float, optional
        One probability per rule, each > 0, summing to 1: how often the chaos game picks each map,
        and so the invariant measure (the gray levels) of the attractor. None (the default) means
        in proportion to ``|det L_i|`` with a floor for nearly singular maps
        (`ifslib.core.geometry.rules.chaos_probabilities`); `measure_probabilities` says which.

    Raises
    ------
    IFSError
        On a bad shape, a NaN point, an out-of-range index, a negative depth or bad probabilities.
    """

    def __init__(self, points: Any, rules: Sequence[Rule | dict], primitives: Sequence[Primitive | dict],
                 depth: int = 3, name: str = "", fixed: Iterable[int] = (), sigma: float | None = None,
                 meta: dict | None = None, dtype: torch.dtype = torch.float32,
                 probabilities: Sequence[float] | None = None) -> None:
        pts = torch.as_tensor(points.detach() if isinstance(points, torch.Tensor) else points, dtype=dtype)
        self.points = pts.clone().requires_grad_(True)
        self.rules = [_as_rule(r) for r in rules]
        self.primitives = [_as_primitive(p) for p in primitives]
        self.depth = depth
        self.name = str(name)
        self.fixed = tuple(sorted(set(int(i) for i in fixed)))
        self.sigma = None if sigma is None else float(sigma)
        self.meta = dict(meta or {})
        self.probabilities = probabilities
        self.validate()

    # -- checks --------------------------------------------------------------------------------
    def validate(self) -> None:
        """Check shapes, indices, finiteness and depth; raise `IFSError` naming the problem."""
        pts = self.points
        if pts.ndim != 2 or pts.shape[1] != 2 or pts.shape[0] == 0:
            raise IFSError(f"points must have shape (n, 2) with n >= 1, got {tuple(pts.shape)}")
        if not pts.dtype.is_floating_point:
            raise IFSError(f"points must be floating point, got {pts.dtype}")
        bad = (~torch.isfinite(pts.detach())).any(dim=1).nonzero().flatten().tolist()
        if bad:
            raise IFSError(f"control point(s) {bad} are not finite (NaN or inf): {pts.detach()[bad].tolist()}")
        n = pts.shape[0]
        if not self.rules:
            raise IFSError("an IFS needs at least one rule")
        if not self.primitives:
            raise IFSError("an IFS needs at least one primitive")
        for i, rule in enumerate(self.rules):
            for j in rule.source + rule.target:
                if not 0 <= j < n:
                    raise IFSError(f"rule {i} uses point index {j}, out of range for {n} points (0..{n - 1})")
        for i, prim in enumerate(self.primitives):
            for j in prim.points:
                if not 0 <= j < n:
                    raise IFSError(f"primitive {i} uses point index {j}, out of range for {n} points (0..{n - 1})")
        for j in self.fixed:
            if not 0 <= j < n:
                raise IFSError(f"fixed point index {j} is out of range for {n} points (0..{n - 1})")
        check_depth(self.depth)
        if self.sigma is not None:
            check_sigma(self.sigma)
        if self.probabilities is not None and len(self.probabilities) != len(self.rules):
            raise IFSError(f"the IFS has {len(self.rules)} rules but {len(self.probabilities)} probabilities; "
                           "give one per rule (or none for the default)")

    def check_contractive(self, depth: int | None = None, maps: torch.Tensor | None = None) -> None:
        """Raise `IFSError` if, while ``depth`` > 0, a rule's map does not contract or is degenerate.

        A map contracts when its largest singular value is below 1 (for a similarity: its scale);
        it is degenerate when its smallest singular value is below `ifslib.core.geometry.rules.MIN_SINGULAR`
        (it flattens the figure onto a line and has no usable inverse).
        """
        depth = self.depth if depth is None else depth
        if depth == 0:
            return
        smallest, largest = singular_values((self.maps() if maps is None else maps).detach())
        for i, (lo, hi) in enumerate(zip(smallest.tolist(), largest.tolist())):
            if not hi < 1:
                raise IFSError(f"rule {i} ({self.rules[i].kind}) is not contractive: its scale is {hi:.4g} >= 1, "
                               f"so depth {depth} > 0 has no attractor to converge to")
            if not lo >= MIN_SINGULAR:
                raise IFSError(f"rule {i} ({self.rules[i].kind}) is degenerate: its smallest singular value is "
                               f"{lo:.3g} (< {MIN_SINGULAR:g}), so it flattens the figure onto a line or a point")

    @property
    def probabilities(self) -> tuple[float, ...] | None:
        """One probability per rule (each > 0, summing to 1), or None for the default; checked when set."""
        return self._probabilities

    @probabilities.setter
    def probabilities(self, value) -> None:
        self._probabilities = None if value is None else check_probabilities(value, len(self.rules))

    # -- maps ----------------------------------------------------------------------------------
    def maps(self, gradient: str = "exact") -> torch.Tensor:
        """The rules' maps as ``(m, 3, 3)`` homogeneous matrices, differentiable in ``points``.

        Parameters
        ----------
        gradient : {"exact", "paper"}
            ``"paper"`` cuts the gradient through segment rules' rotations, as the paper's code did.
        """
        self.validate()
        return rule_maps(self.points, self.rules, gradient)

    def measure_probabilities(self, maps: torch.Tensor | None = None) -> torch.Tensor:
        """Each map's probability, ``(m,)`` float64 (no gradient): the given ``probabilities``, or the default.

        The default is in proportion to ``|det L_i|`` with a floor of
        `ifslib.core.geometry.rules.CHAOS_FLOOR` times the largest, so a flattening map (a fern's
        stem) is still chosen: `ifslib.core.geometry.rules.chaos_probabilities` of ``maps`` (these
        rules' maps when None).
        """
        if self.probabilities is not None:
            return torch.tensor(self.probabilities, dtype=torch.float64)
        return chaos_probabilities(self.maps().detach() if maps is None else maps)

    def scales(self) -> torch.Tensor:
        """Contraction factor of each rule, ``(m,)`` (no gradient): its map's largest singular value."""
        return singular_values(self.maps().detach())[1]

    @property
    def is_similarity(self) -> bool:
        """Whether every rule is a similarity (``segment`` or ``square``), so that ``d_T(S) = s d_S(T^-1 x)`` holds."""
        return all(r.kind != "affine" for r in self.rules)

    @property
    def n_points(self) -> int:
        """Number of control points ``n``."""
        return self.points.shape[0]

    def n_leaves(self, depth: int | None = None) -> int:
        """Number of leaf shapes at ``depth``: ``m**depth * len(primitives)``."""
        depth = self.depth if depth is None else check_depth(depth)
        return len(self.rules) ** depth * len(self.primitives)

    # -- copies --------------------------------------------------------------------------------
    def clone(self, points: Any = None) -> "IFS":
        """A copy with fresh leaf ``points`` (the given ones, or a copy of these)."""
        new = copy.copy(self)
        src = self.points if points is None else torch.as_tensor(points, dtype=self.points.dtype)
        new.points = src.detach().clone().requires_grad_(True)
        new.meta = copy.deepcopy(self.meta)
        new.validate()
        return new

    def jittered(self, jitter: float, rng: np.random.Generator) -> "IFS":
        """A copy with each free point (not in ``fixed``) moved by ``U(-jitter, jitter)`` per coordinate, drawn from ``rng``."""
        points = self.points.detach().double().numpy().copy()
        free = [i for i in range(self.n_points) if i not in self.fixed]
        points[free] += rng.uniform(-jitter, jitter, size=(len(free), 2))
        return self.clone(torch.as_tensor(points, dtype=self.points.dtype))

    def to(self, dtype: torch.dtype) -> "IFS":
        """A copy whose points have floating type ``dtype``."""
        new = self.clone()
        new.points = new.points.detach().to(dtype).requires_grad_(True)
        return new

    def __repr__(self) -> str:
        kinds = sorted({r.kind for r in self.rules})
        prims = sorted({p.kind for p in self.primitives})
        return (f"IFS(name={self.name!r}, points={self.n_points}, rules={len(self.rules)} {'/'.join(kinds)}, "
                f"primitives={len(self.primitives)} {'/'.join(prims)}, depth={self.depth})")


#: How far from 1 the sum of given probabilities may be (a file's decimals rounded, say).
PROBABILITY_SUM_TOLERANCE = 1e-6


def check_probabilities(probabilities: Any, m: int) -> tuple[float, ...]:
    """Return ``m`` probabilities as a tuple of floats if each is finite and > 0 and they sum to 1, else raise `IFSError`.

    A probability of 0 is refused: that map would never be drawn, so its rule should be removed.
    """
    try:
        values = tuple(float(p) for p in (probabilities.tolist() if hasattr(probabilities, "tolist") else probabilities))
    except (TypeError, ValueError):
        raise IFSError(f"probabilities must be a list of {m} numbers, got {probabilities!r}") from None
    if any(isinstance(p, bool) for p in probabilities):
        raise IFSError(f"probabilities must be numbers, not booleans: {probabilities!r}")
    if len(values) != m:
        raise IFSError(f"the IFS has {m} rules but {len(values)} probabilities; give one per rule (or none for the default)")
    bad = [i for i, p in enumerate(values) if not (math.isfinite(p) and p > 0)]
    if bad:
        raise IFSError(f"probability of rule(s) {bad} is not a finite number > 0 ({[values[i] for i in bad]}); "
                       "a map never chosen should be removed from the IFS")
    total = math.fsum(values)
    if abs(total - 1) > PROBABILITY_SUM_TOLERANCE:
        raise IFSError(f"probabilities must sum to 1, they sum to {total:.9g}; divide each by their sum")
    return values


def check_depth(depth: Any) -> int:
    """Return ``depth`` if it is an int >= 0, else raise `IFSError`."""
    return check_int(depth, "depth", 0)


#: The line widths a drawing takes, in plane units (the frame is 1 wide): below, its square underflows
#: float32 (0 / 0 on the figure); above, every pixel of any frame is lit.
SIGMA_RANGE = (1e-12, 1e3)


def check_sigma(sigma: Any) -> float:
    """Return ``sigma`` as a float if it is finite and in `SIGMA_RANGE`, else raise `IFSError`."""
    sigma = check_positive(sigma, "sigma")
    if not SIGMA_RANGE[0] <= sigma <= SIGMA_RANGE[1]:
        raise IFSError(f"sigma must be from {SIGMA_RANGE[0]:g} to {SIGMA_RANGE[1]:g} plane units (the frame is 1 wide), "
                       f"got {sigma!r}")
    return sigma


__all__ = ["IFS", "PROBABILITY_SUM_TOLERANCE", "Rule", "Primitive", "check_depth", "check_probabilities", "check_gradient_mode", "check_rule_lengths"]
