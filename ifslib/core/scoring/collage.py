"""Barnsley's collage distance: how far the union of the maps' copies of the target is from the target.

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

import numpy as np
import torch

from ...errors import IFSError, check_int
from ..geometry.ifs import IFS
from ..targets.target import Target, foreground_points


def sample_foreground(target: Target, n: int, rng: np.random.Generator | int = 0) -> np.ndarray:
    """At most ``n`` of the target's foreground pixel centres ``(min(n, k), 2)``, drawn without replacement
    by ``rng`` (a generator, or the seed of one); all of them, in order, when there are no more than ``n``."""
    fg = foreground_points(target)
    if len(fg) <= n:
        return fg
    rng = np.random.default_rng(rng) if isinstance(rng, (int, np.integer)) else rng
    return fg[rng.choice(len(fg), n, replace=False)]


def lookup(distance: torch.Tensor, points: torch.Tensor) -> torch.Tensor:
    """The target's ``distance`` ``(n, n)`` (plane units) at ``points`` ``(..., 2)``, bilinear, plus the distance to
    the frame outside it: ``(...)``."""
    n = distance.shape[-1]
    flat = points.reshape(1, 1, -1, 2)
    grid = torch.stack([flat[..., 0] * 2, -flat[..., 1] * 2], -1)
    inside = torch.nn.functional.grid_sample(distance.view(1, 1, n, n), grid, mode="bilinear", padding_mode="border",
                                             align_corners=False).view(points.shape[:-1])
    beyond = (points.abs() - (0.5 - 0.5 / n)).clamp(min=0)
    return inside + beyond.square().sum(-1).add(1e-30).sqrt()


def copy_terms(maps: torch.Tensor, points: torch.Tensor, distance: torch.Tensor
               ) -> tuple[torch.Tensor, torch.Tensor]:
    """Each copy's ``outside`` and ``cover`` distances (plane units), for maps ``(..., 2, 3)``: each ``(..., P)``.

    ``outside``: the copy ``T(p)`` of each figure pixel of ``points`` ``(P, 2)``, to the figure;
    ``cover``: each figure pixel ``q`` to the copy ``T(A)``, bounded by ``s d(T^-1 q, A)`` with ``s``
    the map's largest singular value (the module docstring).
    """
    a, t = maps[..., :2], maps[..., 2]
    copies = torch.einsum("...ij,pj->...pi", a, points) + t[..., None, :]
    outside = lookup(distance, copies)
    det = a[..., 0, 0] * a[..., 1, 1] - a[..., 0, 1] * a[..., 1, 0]
    inverse = torch.stack([torch.stack([a[..., 1, 1], -a[..., 0, 1]], -1),
                           torch.stack([-a[..., 1, 0], a[..., 0, 0]], -1)], -2) / det[..., None, None]
    back = torch.einsum("...ij,...pj->...pi", inverse, points - t[..., None, :])
    scale = torch.linalg.matrix_norm(a, ord=2)
    return outside, lookup(distance, back) * scale[..., None]


def collage_terms(maps: torch.Tensor, points: torch.Tensor, distance: torch.Tensor
                  ) -> tuple[torch.Tensor, torch.Tensor]:
    """Mean squared ``outside`` and ``cover`` distances (plane units) of a batch of IFSs: ``maps`` ``(S, k, 2, 3)``.

    ``outside`` is averaged over the copies of every map, ``cover`` takes each figure pixel's
    nearest copy (`copy_terms`). Each ``(S,)``.
    """
    outside, cover = copy_terms(maps, points, distance)
    return outside.square().mean((1, 2)), cover.min(1).values.square().mean(-1)


def collage_distance(ifs: IFS, target: Target, n: int = 2000, seed: int = 0) -> torch.Tensor:
    """The collage distance of ``ifs``'s maps to ``target`` (see the module docstring), differentiable in ``ifs.points``.

    Parameters
    ----------
    ifs : IFS
        Its rules' maps are used; its primitives and depth are not.
    target : Target
    n : int
        Foreground pixels sampled (all of them when fewer).
    seed : int
        Seed of the sample.

    Returns
    -------
    torch.Tensor
        A scalar in squared plane units: ``outside + cover``.
    """
    check_int(n, "n", 1)
    points = torch.as_tensor(sample_foreground(target, n, seed), dtype=ifs.points.dtype)
    outside, cover = collage_terms(ifs.maps()[None, :, :2], points, target.distance.to(ifs.points.dtype))
    return (outside + cover)[0]
