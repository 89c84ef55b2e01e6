"""Sets of candidate copies to start from: covers of the figure and sets of least collage distance.

`greedy_covers` and `beam_covers` pick copies that cover the figure with little overlap;
`collage_sets` picks those with the least collage distance, by a facility-location local search
on each copy's distances (`copy_terms`), computed once.
"""
from __future__ import annotations

import math

import numpy as np
import torch

from ...core.targets.target import Target
from ...core.scoring.collage import copy_terms, sample_foreground
from .config import DEFAULT, SearchConfig


def greedy_covers(feet: torch.Tensor, firsts: int, most: int) -> list[list[int]]:
    """Greedy set covers of the figure by copies of footprints ``feet`` ``(C, n * n)``: from each of the first
    ``firsts`` candidates, ``most - 1`` times the one covering most pixels not yet covered (one matrix product a
    step). The first ``k`` entries of each are a start of ``k`` maps."""
    covers = []
    for first in range(min(firsts, len(feet))):
        covered, chosen = feet[first].clone(), [first]
        for _ in range(most - 1):
            j = int(torch.argmax(feet @ (1 - covered)))
            chosen.append(j)
            covered = torch.maximum(covered, feet[j])
        covers.append(chosen)
    return covers


def beam_covers(feet: torch.Tensor, most: int, *, config: SearchConfig = DEFAULT) -> dict[int, list[list[int]]]:
    """Sets of candidate copies that cover the figure with little overlap, by beam search: ``{k: covers of k copies}``.

    ``feet`` ``(C, n * n)``: each candidate's `footprints`, largest first. A set of copies scores
    the figure pixels it covers minus ``config.overlap`` times those it covers twice or more (the
    copies of a fractal's maps barely overlap, where the copies of a wrong set crowd each other).
    The ``config.beam`` largest copies start; each step adds to every kept set each candidate in
    turn and keeps the ``config.beam`` best distinct sets.
    """
    width, overlap = config.beam, config.overlap
    sizes = feet.sum(1)
    beams = [[i] for i in range(min(width, len(feet)))]
    covered, total = feet[:len(beams)].clone(), sizes[:len(beams)].clone()
    out = {1: [list(b) for b in beams]}
    for k in range(2, most + 1):
        union = covered.sum(1)[:, None] + (1 - covered) @ feet.T            # (B, C)
        score = union - overlap * (total[:, None] + sizes[None] - union)
        for b, beam in enumerate(beams):
            score[b, beam] = -math.inf
        order = torch.argsort(score.reshape(-1), descending=True)
        kept, seen = [], set()
        for flat in order.tolist():
            b, c = divmod(flat, len(feet))
            key = tuple(sorted(beams[b] + [c]))
            if key in seen:
                continue
            seen.add(key)
            kept.append((b, c))
            if len(kept) == width:
                break
        beams = [beams[b] + [c] for b, c in kept]
        covered = torch.stack([torch.maximum(covered[b], feet[c]) for b, c in kept])
        total = torch.stack([total[b] + sizes[c] for b, c in kept])
        out[k] = [list(b) for b in beams]
    return out


def collage_sets(maps: np.ndarray, target: Target, ks, sweeps: int | None = None, seed: int = 0, *,
                 config: SearchConfig = DEFAULT) -> dict[int, list[list[int]]]:
    """Sets of ``k`` of the candidate copies ``maps`` ``(C, 2, 3)`` with the least collage distance: ``{k: sets}``.

    Choosing ``k`` copies so that every figure pixel is near one of them, at the least cost of
    copies outside the figure, is a facility-location problem: each copy's ``outside`` and
    ``cover`` distances are computed once (`copy_terms`, on ``config.collage_points[0]`` figure
    pixels at most), then from each of ``config.restarts`` first copies (the best single copies
    and random ones) the copy that lowers the collage most is added until there are ``k``
    (greedy), and each map in turn is swapped for the candidate that lowers it most, for up to
    ``sweeps`` sweeps (local search; ``config.collage_sweeps`` when None). Distinct sets, best first.
    """
    rng = np.random.default_rng(seed)
    fg = sample_foreground(target, config.collage_points[0], rng)
    with torch.no_grad():
        outside, cover = copy_terms(torch.as_tensor(maps, dtype=torch.float32),
                                    torch.as_tensor(fg, dtype=torch.float32), target.distance.float())
    out, far = outside.square().mean(1), cover.square()                      # (C,), (C, P)
    single = out + far.mean(1)
    half = config.restarts // 2
    firsts = torch.cat([torch.argsort(single)[:half],
                        torch.as_tensor(rng.choice(len(maps), config.restarts - half, replace=False))])
    found = {}
    for k in ks:
        chosen = _greedy(firsts, k, out, far)
        chosen = _local_search(chosen, k, config.collage_sweeps if sweeps is None else sweeps, out, far)
        found[k] = _distinct(chosen, far[chosen].min(1).values.mean(-1) + out[chosen].sum(1) / k)
    return found


def _best_addition(nearest: torch.Tensor, fixed: torch.Tensor, k: int, taken: torch.Tensor, out: torch.Tensor,
                   far: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """For each restart, the candidate (not in ``taken`` ``(R, j)``) whose addition costs least, and that cost.

    ``nearest`` ``(R, P)``: each pixel's squared distance to the restart's other copies; ``fixed``
    ``(R,)``: their summed ``outside``; ``out`` ``(C,)`` and ``far`` ``(C, P)``: each copy's terms.
    """
    cost = torch.cat([torch.minimum(nearest[:, None], far[None, c:c + 512]).mean(-1)
                      for c in range(0, len(far), 512)], 1)
    cost = cost + (fixed[:, None] + out[None]) / k
    cost.scatter_(1, taken, math.inf)
    value, index = cost.min(1)
    return index, value


def _greedy(firsts: torch.Tensor, k: int, out: torch.Tensor, far: torch.Tensor) -> torch.Tensor:
    """``(R, k)`` sets grown from each first copy of ``firsts`` ``(R,)`` by the copy that lowers the collage most."""
    chosen = firsts[:, None].clone()
    for _ in range(k - 1):
        nearest = far[chosen].min(1).values
        index, _ = _best_addition(nearest, out[chosen].sum(1), k, chosen, out, far)
        chosen = torch.cat([chosen, index[:, None]], 1)
    return chosen


def _local_search(chosen: torch.Tensor, k: int, sweeps: int, out: torch.Tensor, far: torch.Tensor) -> torch.Tensor:
    """``chosen`` ``(R, k)`` with each map in turn swapped for the candidate that lowers the collage most, in place,
    for up to ``sweeps`` sweeps (fewer when a sweep changes nothing)."""
    for _ in range(sweeps):
        changed = False
        for i in range(k):
            others = torch.cat([chosen[:, :i], chosen[:, i + 1:]], 1)
            nearest = far[others].min(1).values if k > 1 else torch.full_like(far[:len(chosen)], math.inf)
            index, value = _best_addition(nearest, out[others].sum(1), k, chosen, out, far)
            now = (torch.minimum(nearest, far[chosen[:, i]]).mean(-1) + (out[others].sum(1) + out[chosen[:, i]]) / k)
            better = value < now - 1e-12
            if bool(better.any()):
                changed = True
                chosen[better, i] = index[better]
        if not changed:
            break
    return chosen


def _distinct(chosen: torch.Tensor, total: torch.Tensor) -> list[list[int]]:
    """The distinct sets of ``chosen`` ``(R, k)``, each sorted, least ``total`` ``(R,)`` first."""
    sets, seen = [], set()
    for r in torch.argsort(total).tolist():
        key = tuple(sorted(chosen[r].tolist()))
        if key not in seen:
            seen.add(key)
            sets.append(list(key))
    return sets


def cover_sets(feet: torch.Tensor, ks: tuple[int, ...], *, config: SearchConfig = DEFAULT) -> dict[int, list]:
    """The covers each number of maps of ``ks`` starts from: ``{k: sets of k copies}``, beam covers then greedy ones.

    ``feet`` ``(C, n * n)``: each candidate copy's `footprints`.
    """
    covers = beam_covers(feet, max(ks), config=config)
    for cover in greedy_covers(feet, config.firsts, max(ks)):
        for k in ks:
            covers[k].append(cover[:k])
    return covers
