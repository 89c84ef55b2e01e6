"""The search's judge: maps scored by their attractor, drawn by the chaos game, against the target.

A small collage distance does not make a close attractor (a map of scale 0.8 multiplies a
collage error by five), so every choice the search makes between maps goes by their attractors:
`attractor_iou` and `attractor_chamfer` draw one IFS, `occupancy_iou` ranks a batch of them by a
short chaos game, and `best_trial` keeps the best of a few trials and their refinements.
"""
from __future__ import annotations

import numpy as np
import torch

from ...core.geometry import patterns
from ...core.geometry.attractor import ATTRACTOR
from ...core.geometry.ifs import IFS
from ...core.raster.chaos import chaos_occupancy
from ...core.raster.render import figure_mask
from ...core.scoring.metrics import chamfer, iou
from ...core.targets.target import Target
from .collage import refine
from .config import DEFAULT, SearchConfig


def as_ifs(maps: np.ndarray | torch.Tensor, depth: int = 3) -> IFS:
    """An `ifslib.patterns.affine` IFS of ``maps`` ``(k, 2, 3)``."""
    return patterns.affine(torch.as_tensor(maps).detach().double().numpy(), depth=depth, name="auto")


def _drawn(maps: np.ndarray | torch.Tensor, target: Target, points: int) -> np.ndarray:
    """The maps' attractor drawn by the chaos game (``points`` points) on ``target``'s pixel grid."""
    return figure_mask(as_ifs(maps), target.size, ATTRACTOR, method="chaos", points=points)


def attractor_chamfer(maps: np.ndarray | torch.Tensor, target: Target, points: int | None = None, *,
                      config: SearchConfig = DEFAULT) -> float:
    """Symmetric Chamfer distance (pixels of ``target``) of the attractor of ``maps`` ``(k, 2, 3)``, drawn by the
    chaos game (``points`` points, by default ``config.compare_points``), to the target."""
    return chamfer(_drawn(maps, target, config.compare_points if points is None else points), target.mask)


def attractor_iou(maps: np.ndarray | torch.Tensor, target: Target, points: int | None = None, *,
                  config: SearchConfig = DEFAULT) -> float:
    """IoU of the attractor of ``maps`` ``(k, 2, 3)``, drawn by the chaos game at the target's size (``points``
    points, by default ``config.judge_points``), with the target's mask."""
    return iou(_drawn(maps, target, config.judge_points if points is None else points), target.mask)


def occupancy_iou(batch: torch.Tensor, target: Target, seed: int = 0, chunk: int = 1024) -> torch.Tensor:
    """``(S,)`` IoU with ``target``'s mask of the short chaos games (`chaos_occupancy`) of IFSs ``batch``
    ``(S, k, 2, 3)``: a ranking."""
    figure = torch.as_tensor(target.mask)
    out = []
    for start in range(0, len(batch), chunk):
        drawn = chaos_occupancy(batch[start:start + chunk], target.size, seed=seed)
        out.append((drawn & figure).sum((1, 2)) / (drawn | figure).sum((1, 2)))
    return torch.cat(out)


def best_trial(trials: np.ndarray, fine: Target, judge: Target, seed: int, *,
               config: SearchConfig = DEFAULT) -> tuple[np.ndarray, float]:
    """Of ``trials`` ``(S, k, 2, 3)`` and their collage refinements at ``fine``'s size, the one whose attractor
    (``config.screen_points`` points) overlaps ``fine`` most: its maps ``(k, 2, 3)`` and attractor IoU at
    ``judge``'s size."""
    refined, _ = refine(trials, fine, config.refine_steps, config.refine_lr, config.collage_points[1], seed, config=config)
    variants = np.concatenate([trials, refined.numpy()])
    j = int(np.argmax([iou(_drawn(m, fine, config.screen_points), fine.mask) for m in variants]))
    return variants[j], attractor_iou(variants[j], judge, config=config)
