"""The search's phases, each played on the scoreboard (`Board`): try each number of maps, reorient the best
few, then the moves (`MOVES`) while no reoriented attractor fits.

`try_maps` is steps 2-4 of the package docstring for one number of maps; `reorient_best` picks
the numbers of maps compared at the end and turns their maps (step 4); `regions` (5), `grow` (6)
and `swaps` (7) follow in that order, each only while `Board.stuck`.
"""
from __future__ import annotations

import time

import numpy as np
import torch

from .board import Board, Row
from .candidates import random_starts
from .collage import refine
from .covers import collage_sets
from .judge import attractor_chamfer
from .moves import region_grow, region_swap, reorient, swap
from .scores import least_choice_score


def try_maps(board: Board, k: int) -> None:
    """The first row of ``k`` maps: starts refined on the collage, the best by their attractor kept (steps 2-4)."""
    context, config = board.context, board.config
    coarse, fine, seed = context.coarse, context.fine, context.seed
    t0 = time.perf_counter()
    batch, covered = _starts(board, k)
    work, err = refine(batch, coarse, config.search_steps, config.search_lr, config.collage_points[0], seed, config=config)
    best = torch.argsort(err)[:config.shortlist]
    drawn = np.array([attractor_chamfer(m, fine, config.screen_points) for m in work[best].numpy()])
    best = best[np.argsort(drawn, kind="stable")[:config.keep]]
    if fine.size > coarse.size:  # a target no larger than the search size is refined once
        work, err = refine(work[best], fine, config.refine_steps, config.refine_lr, config.collage_points[1], seed, config=config)
    else:
        work, err = work[best], err[best]
    j = int(np.argmin([attractor_chamfer(m, fine, config.screen_points) for m in work.numpy()]))
    board.judge(Row(maps=k, cover=covered, collage_px=float(err[j])), work[j].numpy())
    board.add_time(k, t0)


def _starts(board: Board, k: int) -> tuple[np.ndarray, float]:
    """The starts of ``k`` maps ``(S, k, 2, 3)`` (the collage's sets, the covers, random maps), and the share of the
    figure the best of the sets covers at the search size."""
    context, config = board.context, board.config
    starts, feet = context.copies.starts, context.copies.feet
    sets = collage_sets(starts, context.coarse, [k], seed=context.seed, config=config)[k] + context.covers[k]
    feet_total = float(context.coarse.mask.sum())
    covered = max(float(feet[c].amax(0).sum()) / feet_total for c in sets)
    batch = np.concatenate([starts[np.array(sets)], random_starts(config.random_starts, k, context.coarse,
                                                                  context.rng, config=config)])
    return batch, covered


def reorient_best(board: Board) -> None:
    """The ``config.reorient`` numbers of maps with the least Chamfer score (which forgives a copy turned the wrong
    way, what reorienting mends, where the IoU does not), each with its maps turned where that helps (`reorient`);
    none when the search gave up."""
    if board.hopeless:
        return
    least = sorted(board.table, key=lambda r: (board.chamfer_score(r), r.maps))[:board.config.reorient]
    board.turned = [r.maps for r in least]
    for k in board.turned:
        t0 = time.perf_counter()
        maps, error = reorient(board.found[k], board.context.fine, seed=board.context.seed, config=board.config)
        board.judge(board.rows[k], maps, reoriented=True, collage_px=error)
        board.add_time(k, t0)


def regions(board: Board) -> None:
    """Each reoriented number of maps, the best scoring first, has maps matched to uncovered regions (step 5)."""
    for row in board.by_score(board.turned_rows):
        region_rounds(board, row.maps)


def region_rounds(board: Board, k: int) -> None:
    """Rounds of `region_swap` for the maps of row ``k`` while a round raises its attractor's IoU and none fits yet."""
    context = board.context
    for _ in range(board.config.region_rounds):
        if not board.stuck():
            return
        t0 = time.perf_counter()
        maps, overlap, kept = region_swap(board.found[k], context.fine, context.judge, context.dense,
                                          seed=context.seed, value=board.rows[k].iou, config=board.config)
        row = board.add_time(k, t0)
        if not kept:
            return
        board.judge(row, maps, overlap, regions=row.regions + 1)


def grow(board: Board) -> None:
    """The best scoring maps and one more, matched to what they leave uncovered, for the next number of maps when
    its attractor beats the next's own (step 6), then that number's region rounds."""
    context, grew = board.context, set()  # the numbers of maps grown from
    for _ in range(board.config.grow_rounds):
        if not board.stuck():
            break
        k = board.best(board.turned_rows).maps
        if k + 1 not in board.rows or k in grew:
            break  # no next number of maps tried, or the best has grown already (nothing changed since)
        grew.add(k)
        t0 = time.perf_counter()
        grown, overlap = region_grow(board.found[k], context.fine, context.judge, context.dense,
                                     seed=context.seed, config=board.config)
        after = board.add_time(k + 1, t0)
        if grown is None or overlap <= after.iou + board.config.accept_margin:
            break
        board.judge(after, grown, overlap, grown=True)
        if k + 1 not in board.turned:
            board.turned.append(k + 1)
        region_rounds(board, k + 1)


def swaps(board: Board) -> None:
    """For the number of maps that scores best, one map at a time replaced by a copy of the pool (`swap`), one round
    at a time, each round that keeps a map followed by region rounds again, until a round keeps nothing for it
    (then the next best) or ``config.swap_rounds`` run out (step 7)."""
    context, config = board.context, board.config
    open_ks, rounds = list(board.turned), config.swap_rounds
    while rounds and open_ks and board.stuck():
        k = board.best([board.rows[j] for j in open_ks]).maps
        if least_choice_score(k, config) >= min(r.score for r in board.turned_rows):
            open_ks.remove(k)  # even an attractor of IoU 1 would not score below the best
            continue
        t0, rounds = time.perf_counter(), rounds - 1
        maps, overlap, kept = swap(board.found[k], context.copies.pool, context.coarse, context.fine, context.judge,
                                   rounds=1, seed=context.seed, value=board.rows[k].iou, config=config)
        row = board.add_time(k, t0)
        if kept:
            board.judge(row, maps, overlap, swapped=row.swapped + 1)
            region_rounds(board, k)
        else:
            open_ks.remove(k)


#: The moves after reorienting, in the order they are tried, each while no reoriented attractor fits.
MOVES = (regions, grow, swaps)
