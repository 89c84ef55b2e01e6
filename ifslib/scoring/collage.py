"""Barnsley's collage distance: how far the union of the maps' copies of the target is from the target.

The collage theorem bounds the distance between an IFS's attractor ``A`` and a target ``T`` by
``h(T, H(T)) / (1 - s)``, with ``H(T) = union_i T_i(T)`` and ``s`` the largest contraction. The
collage distance ``h(T, H(T))`` needs no rendering and no depth: only the maps and the target's
pixels. Here it is a smooth, differentiable stand-in for the Hausdorff distance, on ``n`` of the
target's foreground pixel centres ``P``:

* **outside**: the mean squared distance, to the target, of the copies ``T_i(p)`` (the target's own
  distance transform, read between pixels by bilinear interpolation, `torch.nn.functional.grid_sample`);
* **cover**: the mean squared distance from each ``p`` to its nearest copy ``T_i(p')`` (the nearest one
  found by `scipy.spatial.cKDTree`, the distance to it differentiated).

`collage_prefit` moves an IFS's free control points to lower it: a cheap fit of the maps alone, before
the rendered fit.
"""
from __future__ import annotations

import math

import numpy as np
import torch
from scipy.spatial import cKDTree

from ..errors import IFSError, check_int
from ..geometry.ifs import IFS
from ..targets.target import Target, foreground_points


def _sample(target: Target, n: int, seed: int) -> torch.Tensor:
    fg = foreground_points(target)
    if len(fg) > n:
        fg = fg[np.random.default_rng(seed).choice(len(fg), n, replace=False)]
    return torch.as_tensor(fg, dtype=torch.float64)


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
    p = _sample(target, n, seed).to(ifs.points.dtype)
    maps = ifs.maps()
    copies = (p @ maps[:, :2, :2].transpose(1, 2) + maps[:, None, :2, 2]).reshape(-1, 2)  # (m * n, 2)
    # the target's distance at the copies: plane (x, y) -> grid_sample's (x, -y) * 2, pixel centres as in
    # docs/guide/conventions.md
    grid = torch.stack([copies[:, 0] * 2, -copies[:, 1] * 2], -1).view(1, 1, -1, 2)
    dist = target.distance.to(copies.dtype).view(1, 1, target.size, target.size)
    outside = torch.nn.functional.grid_sample(dist, grid, mode="bilinear", padding_mode="border",
                                              align_corners=False).square().mean()
    nearest = cKDTree(copies.detach().cpu().numpy()).query(p.numpy())[1]
    cover = (p - copies[torch.as_tensor(nearest)]).square().sum(-1).mean()
    return outside + cover


def collage_prefit(ifs: IFS, target: Target, steps: int = 200, lr: float = 0.003, n: int = 2000,
                   seed: int = 0) -> tuple[IFS, list[float]]:
    """Adam on the free control points, minimizing `collage_distance`; a step that stops a map contracting ends it.

    Returns
    -------
    IFS
        The points with the lowest collage distance seen (a copy).
    list of float
        The collage distance at every step.
    """
    check_int(steps, "steps", 0)
    if not (isinstance(lr, (int, float)) and lr > 0 and math.isfinite(lr)):
        raise IFSError(f"lr must be a finite number > 0, got {lr!r}")
    work = ifs.clone()
    opt = torch.optim.Adam([work.points], lr=lr)
    history, best, best_points = [], math.inf, work.points.detach().clone()
    for _ in range(steps):
        try:
            work.check_contractive(max(work.depth, 1))
        except IFSError:
            break
        opt.zero_grad(set_to_none=True)
        value = collage_distance(work, target, n, seed)
        value.backward()
        if work.fixed:
            work.points.grad[list(work.fixed)] = 0
        history.append(value.item())
        if history[-1] < best:
            best, best_points = history[-1], work.points.detach().clone()
        opt.step()
    return ifs.clone(best_points), history
