"""The descent on the collage distance of a batch of IFSs (`refine`): the search's maps moved until their copies of
the figure rebuild it (the distance itself is `ifslib.core.scoring.collage`'s)."""
from __future__ import annotations

import numpy as np
import torch

from ...core.fitting.descent import Descent, StepPolicy
from ...core.scoring.collage import collage_terms, sample_foreground
from ...core.targets.target import Target
from .config import DEFAULT, SearchConfig


def clamp_scales(maps: torch.Tensor, low: float | None = None, high: float | None = None) -> None:
    """Clamp the singular values of every map's linear part (``maps[..., :2, :2]``) into [``low``, ``high``],
    in place."""
    u, s, vh = torch.linalg.svd(maps[..., :2])
    maps[..., :2] = u @ torch.diag_embed(s.clamp(low, high)) @ vh


def refine(maps: np.ndarray | torch.Tensor, target: Target, steps: int, lr: float, points: int,
           seed: int = 0, *, config: SearchConfig = DEFAULT) -> tuple[torch.Tensor, torch.Tensor]:
    """Adam on a batch of IFSs' maps ``(S, k, 2, 3)`` (plane units), minimizing their collage distance to ``target``.

    The collage is taken on at most ``points`` figure pixels (drawn by ``seed``), and every map's
    singular values are clipped into ``config``'s scales after each step. Returns the maps
    ``(S, k, 2, 3)`` after ``steps`` steps and each IFS's collage distance ``(S,)``, the root of
    ``outside + cover`` in pixels of the target.
    """
    p = torch.as_tensor(sample_foreground(target, points, seed), dtype=torch.float32)
    distance = target.distance.float()
    work = torch.as_tensor(maps, dtype=torch.float32).clone()
    with torch.no_grad():
        clamp_scales(work, config.min_scale, config.max_scale)
    work.requires_grad_(True)
    pixel2 = float(target.size) ** 2

    def loss() -> torch.Tensor:
        outside, cover = collage_terms(work, p, distance)
        return ((outside + cover) * pixel2).sum()

    keep = StepPolicy(contract=lambda _: clamp_scales(work, config.min_scale, config.max_scale),
                      advice="the collage distance is not finite: lower the search's learning rate")
    Descent([{"params": [work], "lr": lr}], loss, keep).run(steps)
    with torch.no_grad():
        outside, cover = collage_terms(work, p, distance)
    return work.detach().double(), ((outside + cover) * pixel2).sqrt().double()
