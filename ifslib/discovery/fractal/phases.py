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

from .board import Board
from .candidates import random_starts
from .collage import refine
from .covers import collage_sets
from .judge import attractor_chamfer
from .moves import region_grow, region_swap, reorient, swap


def try_maps(board: Board, k: int) -> None:
    """The first row of ``k`` maps: starts refined on the collage, the best by their attractor kept (steps 2-4)."""
    context, config = board.context, board.config
    coarse, fine, seed = context.coarse, context.fine, context.seed
    t0 = time.perf_counter()
    batch, covered = _starts(board, k)
    work, err = refine(batch, coarse, config.search_steps, 0.005, config.collage_points[0], seed, config=config)
    best = torch.argsort(err)[:config.shortlist]
    drawn = np.array([attractor_chamfer(m, fine, config.screen_points) for m in work[best].numpy()])
    best = best[np.argsort(drawn, kind="stable")[:config.keep]]
    if fine.size > coarse.size:  # a target no larger than the search size is refined once
        work, err = refine(work[best], fine, config.refine_steps, 0.002, config.collage_points[1], seed, config=config)
    else:
        work, err = work[best], err[best]
    j = int(np.argmin([attractor_chamfer(m, fine, config.screen_points) for m in work.numpy()]))
    row = {"maps": k, "cover": round(covered, 4), "collage_px": round(float(err[j]), 4)}
    board.judge(row, work[j].numpy())
    row["seconds"] = round(time.perf_counter() - t0, 2)
    board.table.append(row)


def _starts(board: Board, k: int) -> tuple[np.ndarray, float]:
    """The starts of ``k`` maps ``(S, k, 2, 3)`` (the collage's sets, the covers, random maps), and the share of the
    figure the best of the sets covers at the search size."""
    context, config = board.context, board.config
    starts, feet = context.copies.starts, context.copies.feet
    sets = collage_sets(starts, context.coarse, [k], seed=context.seed, config=config)[k] + context.covers[k]
    feet_total = float(context.coarse.mask.sum())
    covered = max(float(feet[c].amax(0).sum()) / feet_total for c in sets)
    batch = np.concatenate([starts[np.array(sets)], random_starts(config.random_starts, k, context.coarse,
                                                                  context.rng)])
    return batch, covered


def reorient_best(board: Board) -> None:
    """The ``config.reorient`` numbers of maps with the least Chamfer score (which forgives a copy turned the wrong
    way, what reorienting mends, where the IoU does not), each with its maps turned where that helps (`reorient`);
    none when the search gave up."""
    if board.hopeless:
        return
    board.turned = sorted(board.table, key=lambda r: (board.chamfer_score(r), r["maps"]))[:board.config.reorient]
    for row in board.turned:
        t0 = time.perf_counter()
        maps, error = reorient(board.found[row["maps"]], board.context.fine, seed=board.context.seed,
                               config=board.config)
        row["reoriented"] = True
        row["collage_px"] = round(error, 4)
        board.judge(row, maps)
        board.add_time(row, t0)


def regions(board: Board) -> None:
    """Each reoriented number of maps, the best scoring first, has maps matched to uncovered regions (step 5)."""
    for row in board.by_score(board.turned):
        region_rounds(board, row)


def region_rounds(board: Board, row: dict) -> None:
    """Rounds of `region_swap` for ``row``'s maps while a round raises its attractor's IoU and none fits yet."""
    context, k = board.context, row["maps"]
    for _ in range(board.config.region_rounds):
        if not board.stuck():
            return
        t0 = time.perf_counter()
        maps, overlap, kept = region_swap(board.found[k], context.fine, context.judge, context.dense,
                                          seed=context.seed, value=board.overlaps[k], config=board.config)
        board.add_time(row, t0)
        if not kept:
            return
        row["regions"] = row.get("regions", 0) + 1
        board.judge(row, maps, overlap)


def grow(board: Board) -> None:
    """The best scoring maps and one more, matched to what they leave uncovered, for the next number of maps when
    its attractor beats the next's own (step 6), then that number's region rounds."""
    context, grew = board.context, set()  # the numbers of maps grown from
    for _ in range(board.config.grow_rounds):
        if not board.stuck():
            break
        row = board.best(board.turned)
        after = board.row(row["maps"] + 1)
        if after is None or row["maps"] in grew:
            break  # no next number of maps tried, or the best has grown already (nothing changed since)
        grew.add(row["maps"])
        t0 = time.perf_counter()
        grown, overlap = region_grow(board.found[row["maps"]], context.fine, context.judge, context.dense,
                                     seed=context.seed, config=board.config)
        board.add_time(after, t0)
        if grown is None or overlap <= board.overlaps[after["maps"]] + 1e-3:
            break
        after["grown"] = True
        board.judge(after, grown, overlap)
        if after not in board.turned:
            board.turned.append(after)
        region_rounds(board, after)


def swaps(board: Board) -> None:
    """For the number of maps that scores best, one map at a time replaced by a copy of the pool (`swap`), one round
    at a time, each round that keeps a map followed by region rounds again, until a round keeps nothing for it
    (then the next best) or ``config.swap_rounds`` run out (step 7)."""
    context, config = board.context, board.config
    open_rows, rounds = list(board.turned), config.swap_rounds
    while rounds and open_rows and board.stuck():
        row = board.best(open_rows)
        k = row["maps"]
        if config.map_cost * k >= min(r["score"] for r in board.turned):
            open_rows.remove(row)  # even an attractor of IoU 1 would not score below the best
            continue
        t0, rounds = time.perf_counter(), rounds - 1
        maps, overlap, kept = swap(board.found[k], context.copies.pool, context.coarse, context.fine, context.judge,
                                   rounds=1, seed=context.seed, value=board.overlaps[k], config=config)
        board.add_time(row, t0)
        if kept:
            row["swapped"] = row.get("swapped", 0) + 1
            board.judge(row, maps, overlap)
            region_rounds(board, row)
        else:
            open_rows.remove(row)


#: The moves after reorienting, in the order they are tried, each while no reoriented attractor fits.
MOVES = (regions, grow, swaps)
