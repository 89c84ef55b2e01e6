"""Moves that mend a search's maps, each kept only when the attractor gets closer to the target.

`reorient` turns maps by the figure's near-symmetries (`turns`); `region_swap` replaces a map, or
two, by copies matched to what the other copies leave uncovered (`regions`); `region_grow` adds
one such map; `swap` replaces one map at a time by a copy of the candidates' pool.
"""
from __future__ import annotations

import itertools
import math

import numpy as np
import torch

from ...core.targets.target import Target, foreground_points
from .collage import refine
from .config import DEFAULT, SearchConfig
from .judge import attractor_chamfer, attractor_iou, best_trial, occupancy_iou
from ..moments import sqrtm_psd
from .regions import region_maps, rotation, uncovered_maps


def turns(target: Target, *, config: SearchConfig = DEFAULT) -> np.ndarray:
    """``(2 * count - 1, 2, 3)`` maps that keep the figure's mean and covariance: its likely near-symmetries.

    ``S = mu + C^1/2 R C^-1/2 (x - mu)`` for ``R`` each of ``count = config.turns`` rotations, with and without a
    reflection, the identity left out. A copy ``T_i(A)`` is nearly the same set as ``T_i(S(A))``,
    so at a coarse size a map can lock onto the copy turned the wrong way; `reorient` tries them.
    """
    fg = foreground_points(target)
    mu, root = fg.mean(0), sqrtm_psd(np.cov(fg.T))
    inverse = np.linalg.inv(root)
    count = config.turns
    out = []
    for angle in np.arange(count) * 2 * math.pi / count:
        for sign in (1.0, -1.0):
            linear = root @ rotation(angle) @ np.diag([1.0, sign]) @ inverse
            out.append(np.concatenate([linear, (mu - linear @ mu)[:, None]], 1))
    return np.array(out[1:])


def reorient(maps: np.ndarray, target: Target, rounds: int = 3, seed: int = 0, *,
             config: SearchConfig = DEFAULT) -> tuple[np.ndarray, float]:
    """Try each of ``maps`` ``(k, 2, 3)`` turned by each of `turns` (``T_i o S``), keep the collage's best, repeat.

    Every variant (one map turned, the others kept) is scored by its collage distance at once;
    the ``config.screen`` best and the maps as given are refined together (`refine`), and the one
    whose attractor is closest to the target (`attractor_chamfer`, ``config.screen_points``
    points) is kept. Stops after ``rounds`` rounds or when the maps as given stay best.

    Returns
    -------
    numpy.ndarray
        ``(k, 2, 3)`` the maps.
    float
        Their collage distance in pixels of ``target``.
    """
    symmetric = turns(target, config=config)
    maps = np.asarray(maps, dtype=np.float64)
    error = math.inf
    for _ in range(rounds):
        batch = [maps]
        for i in range(len(maps)):
            for s in symmetric:
                turned = maps.copy()
                turned[i, :, :2] = maps[i, :, :2] @ s[:, :2]
                turned[i, :, 2] = maps[i, :, :2] @ s[:, 2] + maps[i, :, 2]
                batch.append(turned)
        batch = np.array(batch)
        _, first = refine(batch, target, 0, 0.0, config.collage_points[1], seed, config=config)
        keep = torch.cat([torch.tensor([0]), 1 + torch.argsort(first[1:])[:config.screen]])
        work, err = refine(batch[keep.numpy()], target, config.refine_steps, config.refine_lr, config.collage_points[1], seed,
                           config=config)
        scores = [attractor_chamfer(m, target, config.screen_points) for m in work.numpy()]
        best = int(np.argmin(scores))
        maps, error = work[best].numpy(), float(err[best])
        if best == 0:
            break
    return maps, error


def swap(maps: np.ndarray, pool: np.ndarray, coarse: Target, fine: Target, judge: Target, *, rounds: int = 1,
         seed: int = 0, value: float | None = None, config: SearchConfig = DEFAULT) -> tuple[np.ndarray, float, int]:
    """Replace one map at a time by a copy of ``pool``, ranked by the attractor; keep what raises its IoU.

    The search's sets are made by the collage, which places the large copies well and often
    misses a thin or small one (its copy covers few pixels, and a wrong set covers the coarse
    figure's stray pixels better). The attractor tells them apart: each round, every IFS with one
    map replaced by one copy of the pool (``k * len(pool)`` of them) is drawn by a short chaos
    game at ``coarse``'s size (`chaos_occupancy`) and ranked by its IoU with ``coarse``; the
    ``config.swap_top`` best are refined on the collage at ``fine``'s size (`refine`), and of them and
    their unrefined selves the one whose attractor (`best_trial`) overlaps ``fine`` most is
    kept when its attractor IoU at ``judge``'s size beats the maps' by more than ``config.accept_margin``. Stops after
    ``rounds`` rounds or a round that keeps nothing.

    Parameters
    ----------
    maps : numpy.ndarray
        ``(k, 2, 3)`` the maps, plane units.
    pool : numpy.ndarray
        ``(C, 2, 3)`` the copies that may replace a map.
    coarse, fine, judge : Target
        The target at the ranking, refining and judging sizes.
    rounds : int
        Rounds at most.
    seed : int
        Seeds the chaos games and the collage's pixel sample.
    value : float, optional
        The maps' attractor IoU at ``judge``'s size (`attractor_iou`), when the caller has it.
    config : SearchConfig
        The settings (``swap_top``, and those of `best_trial`).

    Returns
    -------
    numpy.ndarray
        ``(k, 2, 3)`` the maps.
    float
        Their attractor IoU at ``judge``'s size (`attractor_iou`).
    int
        The rounds that replaced a map.
    """
    maps = np.asarray(maps, dtype=np.float64)
    value, kept = attractor_iou(maps, judge, config=config) if value is None else value, 0
    copies = torch.as_tensor(pool, dtype=torch.float32)
    for _ in range(rounds):
        ranks = []
        for i in range(len(maps)):
            batch = torch.as_tensor(maps, dtype=torch.float32).expand(len(copies), -1, -1, -1).clone()
            batch[:, i] = copies
            ranks.append(occupancy_iou(batch, coarse, seed))
        best = torch.argsort(torch.cat(ranks), descending=True)[:config.swap_top].tolist()
        trials = np.repeat(maps[None], len(best), 0)
        for t, flat in enumerate(best):
            trials[t, flat // len(pool)] = pool[flat % len(pool)]
        replaced, overlap = best_trial(trials, fine, judge, seed, config=config)
        if overlap <= value + config.accept_margin:
            break
        maps, value, kept = replaced, overlap, kept + 1
    return maps, value, kept


def region_swap(maps: np.ndarray, fine: Target, judge: Target, points: np.ndarray, *, seed: int = 0,
                value: float | None = None, config: SearchConfig = DEFAULT) -> tuple[np.ndarray, float, bool]:
    """One round of replacing a map, or two, by copies matched to the figure's uncovered regions (`regions`).

    For each map, the figure pixels the other maps' copies leave uncovered are matched by moments
    (`region_maps`, a few maps each); every IFS with one map, or two maps, replaced by such maps
    (a pair: two thin maps are often missed together, and one alone does not raise the IoU) is
    drawn by a short chaos game at ``fine``'s size and ranked by its IoU with it; the
    ``config.region_top`` best are refined on the collage and the best by their attractor is kept when its IoU at
    ``judge``'s size beats the maps' by more than ``config.accept_margin``.

    Parameters and returns are those of `swap` (``fine`` ranks and refines, ``judge`` judges), but
    for ``points``, ``(P, 2)`` plane points of the figure denser than ``fine`` (its pixels at
    ``judge``'s size) that draw the copies, and the last value returned, a bool: whether a
    replacement was kept.
    """
    maps = np.asarray(maps, dtype=np.float64)
    value = attractor_iou(maps, judge, config=config) if value is None else value
    offers = [region_maps(maps, i, fine.mask, points, config=config) for i in range(len(maps))]
    trials = [_replaced(maps, {i: m}) for i, ms in enumerate(offers) for m in ms]
    for i, j in itertools.combinations(range(len(maps)), 2):
        trials += [_replaced(maps, {i: a, j: b}) for a in offers[i] for b in offers[j]]
    if not trials:
        return maps, value, False
    trials = np.array(trials)
    ranks = occupancy_iou(torch.as_tensor(trials, dtype=torch.float32), fine, seed)
    best = torch.argsort(ranks, descending=True)[:config.region_top].numpy()
    replaced, overlap = best_trial(trials[best], fine, judge, seed, config=config)
    if overlap <= value + config.accept_margin:
        return maps, value, False
    return replaced, overlap, True


def region_grow(maps: np.ndarray, fine: Target, judge: Target, points: np.ndarray, *, seed: int = 0,
                config: SearchConfig = DEFAULT) -> tuple[np.ndarray | None, float]:
    """``maps`` ``(k, 2, 3)`` and one more, matched to the region all their copies leave uncovered (`uncovered_maps`).

    Each offer is added to the maps, refined on the collage, and the IFS whose attractor overlaps
    ``fine`` most is returned with its attractor IoU at ``judge``'s size; ``(None, 0.0)`` when the
    copies leave nothing uncovered. Where a search keeps the right maps but one too few (the
    missing copy left bare), this gives the next number of maps those maps rather than a new start.
    """
    maps = np.asarray(maps, dtype=np.float64)
    offers = uncovered_maps(maps, fine.mask, points, config=config)
    if not len(offers):
        return None, 0.0
    trials = np.array([np.concatenate([maps, m[None]]) for m in offers])
    return best_trial(trials, fine, judge, seed, config=config)


def _replaced(maps: np.ndarray, new: dict) -> np.ndarray:
    """A copy of ``maps`` ``(k, 2, 3)`` with map ``i`` replaced by ``new[i]`` ``(2, 3)`` for each key."""
    out = maps.copy()
    for i, m in new.items():
        out[i] = m
    return out
