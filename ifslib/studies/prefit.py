"""A start's control points moved by Adam on Barnsley's collage distance (`ifslib.core.scoring.collage`)
before any rendering: the pre-fit `benchmarks/collage.py` measures against the plain start."""
from __future__ import annotations

import math

import torch

from ..core.geometry.ifs import IFS
from ..core.scoring.collage import collage_distance
from ..core.targets.target import Target
from ..errors import IFSError, check_int


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
