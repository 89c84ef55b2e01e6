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
from ...core.geometry.rules import chaos_probabilities
from ...core.geometry.attractor import ATTRACTOR
from ...core.geometry.ifs import IFS
from ...core.raster.render import figure_mask
from ...core.scoring.metrics import chamfer, iou
from ...core.targets.target import Target
from .collage import refine
from ...errors import IFSError, check_int
from .config import DEFAULT, SearchConfig


def chaos_occupancy(maps: torch.Tensor, size: int, chains: int = 48, steps: int = 48, burn: int = 8,
                    seed: int = 0) -> torch.Tensor:
    """The pixels a short chaos game visits, for a batch of IFSs at once: a cheap, noisy picture of each attractor.

    Each IFS runs ``chains`` chains from the fixed point of its first map (a point of the
    attractor) for ``burn + steps`` steps in float32, and the pixels of the last ``steps`` points
    are marked: ``chains * steps`` points an IFS. Far fewer points than `chaos_game` draws, so a
    rarely visited part of an attractor may be missed: it ranks many IFSs against one another
    (`ifslib.automatic.fractal.swap`), it does not score one.

    Parameters
    ----------
    maps : torch.Tensor
        ``(S, k, 2, 3)`` (or ``(S, k, 3, 3)``) maps ``[L | t]`` of ``S`` IFSs of ``k`` maps each,
        plane units; each must contract (not checked: a map that does not contract sends its
        chains out of the frame, where they mark nothing).
    size : int
        Pixels per side of the frame ``[-0.5, 0.5]²``.
    chains, steps, burn : int
        Chains per IFS, the steps whose points are marked, and the steps before them.
    seed : int
        Seeds the choice of maps (`torch.Generator`).

    Returns
    -------
    torch.Tensor
        ``(S, size, size)`` bool, row 0 at the top (``y = 0.5``).
    """
    check_int(size, "size", 1)
    for value, name in [(chains, "chains"), (steps, "steps")]:
        check_int(value, name, 1)
    check_int(burn, "burn", 0)
    maps = torch.as_tensor(maps, dtype=torch.float32)
    if maps.dim() != 4 or maps.shape[-1] != 3 or maps.shape[-2] not in (2, 3):
        raise IFSError(f"chaos_occupancy takes maps of shape (S, k, 2, 3), got {tuple(maps.shape)}")
    count, k = maps.shape[:2]
    generator = torch.Generator().manual_seed(seed)
    cdf = chaos_probabilities(maps).float().cumsum(-1)
    coef = maps[..., :2, :].reshape(count, k, 6)                 # a, b, tx, c, d, ty
    first = maps[:, 0, :2, :]
    start = torch.linalg.solve(torch.eye(2) - first[..., :2], first[..., 2])
    x = start[:, :1].expand(count, chains).contiguous()
    y = start[:, 1:].expand(count, chains).contiguous()
    picks = torch.searchsorted(cdf, torch.rand(count, (burn + steps) * chains, generator=generator)).clamp_(max=k - 1)
    step = torch.gather(coef, 1, picks[..., None].expand(-1, -1, 6)).view(count, burn + steps, chains, 6)
    marked = torch.zeros(count, size * size + 1)
    for s in range(burn + steps):
        a = step[:, s]
        x, y = a[..., 0] * x + a[..., 1] * y + a[..., 2], a[..., 3] * x + a[..., 4] * y + a[..., 5]
        if s >= burn:
            col, row = ((x + 0.5) * size).floor(), ((0.5 - y) * size).floor()
            inside = (col >= 0) & (col < size) & (row >= 0) & (row < size)
            flat = torch.where(inside, row * size + col, torch.full_like(col, size * size)).long()
            marked.scatter_(1, flat, 1.0)
    return marked[:, :-1].view(count, size, size) > 0

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
