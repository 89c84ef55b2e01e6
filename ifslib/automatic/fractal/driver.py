"""`search`: the phases of one search on a scoreboard, the number of maps chosen, and the runs again (step 8).

One search (`_search`) tries each number of maps (`phases.try_maps`), reorients the best few,
plays the moves while no attractor fits, and chooses the number of maps by minimum description
length; `search` runs it again from the next seed while no attractor fits.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
from tqdm.auto import tqdm

from ...errors import IFSError, check_int
from ...progress import draw_bars, note
from ...core.targets.target import Target, foreground_points, resize_target
from .board import Board, Context, Row
from .candidates import candidate_copies
from .config import DEFAULT, SearchConfig
from .covers import cover_sets
from .phases import MOVES, reorient_best, try_maps


@dataclass
class SearchResult:
    """What `search` found.

    Attributes
    ----------
    maps : numpy.ndarray
        ``(k, 2, 3)`` the chosen maps ``[A | t]``, plane units.
    rows : tuple of Row
        One `Row` per number of maps tried, in the order tried, at full precision: what decides.
    rule : str
        How the number of maps was chosen, in words.
    learned : bool
        Whether the chosen maps are the learned guess's (its row is the last, `Row.learned`).
    """

    maps: np.ndarray
    rows: tuple[Row, ...] = ()
    rule: str = ""
    learned: bool = False

    @property
    def choice(self) -> Row:
        """The row of the chosen maps."""
        return next(row for row in self.rows if row.maps == len(self.maps) and row.learned == self.learned)

    @property
    def table(self) -> list[dict]:
        """The rows as the file writes them (`Row.written`): ``maps``, ``cover`` (share of the figure the greedy
        copies covered at ``search_size``), ``collage_px`` (at ``refine_size``), ``chamfer_px`` (the attractor's,
        at ``refine_size``), ``iou`` (the attractor's, at ``judge_size``), ``score`` (``1 - iou + map_cost *
        maps``), ``seconds``; ``reoriented``, ``regions``, ``grown`` and ``swapped`` where they apply."""
        return [row.written() for row in self.rows]

    @property
    def chosen(self) -> dict:
        """The chosen row as the file writes it."""
        return self.choice.written()


def check_maps(maps, *, config: SearchConfig = DEFAULT) -> tuple[int, ...]:
    """The numbers of maps to compare: ``config.fractal_maps`` for None, else those given (an int or a sequence,
    each 1 to ``config.max_maps``), sorted."""
    if maps is None:
        return config.fractal_maps
    ks = tuple(maps) if isinstance(maps, (list, tuple, range)) else (maps,)
    if not ks:
        raise IFSError("give at least one number of maps to compare")
    for k in ks:
        check_int(k, "number of maps", 1)
        if k > config.max_maps:
            raise IFSError(f"a fractal search takes at most {config.max_maps} maps, got {k}")
    return tuple(sorted(set(ks)))


def search(target: Target, maps=None, *, seed: int = 0, progress: bool = True,
           config: SearchConfig = DEFAULT) -> SearchResult:
    """Find the affine maps of a fractal from its image (see the package docstring).

    When no number of maps draws an attractor of IoU ``config.swap_below`` or more (and the
    search did not give up), the search runs again from ``seed + 1``, up to ``config.again``
    times (its moves take other paths from other random starts and pixel samples), and the
    search whose chosen maps score least is returned.

    Parameters
    ----------
    target : Target
        The fractal's image; it is matched at ``config.search_size`` and refined at
        ``config.refine_size`` (or at its own size when smaller).
    maps : int or sequence of int, optional
        The numbers of maps to compare (one: fix it); by default each of ``config.fractal_maps``.
    seed : int
        Seeds the random starts and the pixel samples.
    progress : bool
        A progress bar over the numbers of maps.
    config : SearchConfig
        The settings; `DEFAULT` by default (``dataclasses.replace(DEFAULT, again=0)`` changes one).

    Returns
    -------
    SearchResult
    """
    if not isinstance(config, SearchConfig):
        raise IFSError(f"config must be a SearchConfig (dataclasses.replace(fractal.DEFAULT, ...)), got {config!r}")
    ks = check_maps(maps, config=config)
    first = _context(target, ks, seed, config)
    found = _search(first, ks, progress, "fractal search")
    tries = [found]
    for run in range(1, config.again + 1):
        if max(r.iou for r in found.rows) >= config.swap_below or not any(r.reoriented for r in found.rows):
            break  # an attractor fits, or the search gave up (not a fractal of a few maps: nothing reoriented)
        again = dataclasses.replace(first, rng=np.random.default_rng(seed + run), seed=seed + run)
        tries.append(_search(again, ks, progress, f"fractal search again (seed {seed + run})"))
        found = min(tries, key=lambda r: (r.choice.score, len(r.maps)))
    if len(tries) > 1:
        scores = ", ".join(f"{r.choice.score:.3f}" for r in tries)
        found.rule += (f"; no attractor reached IoU {config.swap_below}, so the search ran from seeds "
                       f"{seed}-{seed + len(tries) - 1}, whose chosen maps scored {scores}: the least was kept")
    return found


def _context(target: Target, ks: tuple[int, ...], seed: int, config: SearchConfig) -> Context:
    """What one search from ``seed`` reads: the target at its sizes, its candidate copies and their covers (which
    do not depend on the seed: a search again from another seed reads the same, with the seed's ``rng``)."""
    rng = np.random.default_rng(seed)
    coarse = resize_target(target, min(config.search_size, target.size))
    fine = resize_target(target, min(config.refine_size, target.size))
    judge = resize_target(target, min(config.judge_size, target.size))
    copies = candidate_copies(coarse, config=config)
    covers = cover_sets(copies.feet, ks, config=config)
    return Context(coarse, fine, judge, copies, covers, foreground_points(judge), rng, seed, config)


def _search(context: Context, ks: tuple[int, ...], progress: bool, title: str) -> SearchResult:
    """One search from ``context`` of the numbers of maps ``ks`` (`search` without its runs again), ``title`` on its
    progress bar."""
    board = Board(context)
    fine = context.fine
    for k in tqdm(ks, desc=f"{title} · {fine.size}² · maps", disable=not (progress and draw_bars())):
        if not board.declines(k):
            try_maps(board, k)
    reorient_best(board)
    for move in MOVES:
        if not board.stuck():
            break
        move(board)
    if progress and not draw_bars():
        note(f"{title}: " + ", ".join(f"{r.maps} maps IoU {r.iou:.3f}, {r.chamfer_px:.2f} px" for r in board.table))
    chosen = board.best()
    return SearchResult(board.found[chosen.maps], tuple(board.table), _rule(board, chosen))


def _rule(board: Board, chosen: Row) -> str:
    """How the number of maps was chosen, and what each phase did, in words."""
    config, table = board.config, board.table
    rule = (f"fewest maps for the fit: least 1 - attractor IoU at {board.context.judge.size}² plus {config.map_cost} "
            f"a map (minimum description length), among the {config.reorient} reoriented (the least attractor "
            f"Chamfer distance at {board.context.fine.size}² plus {config.chamfer_cost} px a map); "
            f"{chosen.maps} maps scored {chosen.score:.3f}")
    regions = [r for r in table if r.regions]
    if regions:
        rule += "; " + ", ".join(f"{r.maps} maps had {r.regions} round(s) of maps matched to uncovered regions"
                                 for r in regions) + f" (the reoriented attractor's IoU was below {config.swap_below})"
    swapped = [r for r in table if r.swapped]
    if swapped:
        rule += "; " + ", ".join(f"{r.maps} maps had {r.swapped} map(s) swapped" for r in swapped) + \
                f" (no reoriented attractor reached IoU {config.swap_below})"
    if board.hopeless:
        rule += (f"; {', '.join(map(str, board.hopeless))} maps not tried, and none reoriented: up to "
                 f"{config.give_up_maps} maps no attractor came within {config.give_up_px} px of the target")
    if board.skipped:
        rule += (f"; {', '.join(map(str, board.skipped))} maps not tried: with {config.chamfer_cost} px a map their "
                 f"Chamfer distance scores at least {config.chamfer_cost * board.skipped[0]:.1f}, no less than the "
                 "best already found")
    return rule
