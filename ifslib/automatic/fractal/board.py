"""The scoreboard of one search: a `Row` per number of maps tried, the maps found, and how they score.

Every decision of the search reads a `Row`'s full-precision values; `Row.written` rounds them once,
for `SearchResult.table` and the file. `Context` is what every step of the search reads and none changes.
"""
from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field

import numpy as np

from ...core.targets.target import Target
from .candidates import Copies
from .config import SearchConfig
from .judge import attractor_chamfer, attractor_iou
from .scores import choice_score, least_trial_score, trial_score


@dataclass(frozen=True)
class Context:
    """What every step of one search reads: the target at its three sizes, the candidate copies, the settings.

    Attributes
    ----------
    coarse, fine, judge : Target
        The target at the search, refining and judging sizes (each at most the target's own).
    copies : Copies
        The candidate copies found at ``coarse``'s size.
    covers : dict
        ``{k: sets of k indices into copies.starts}``: the covers each number of maps starts from.
    dense : numpy.ndarray
        ``(P, 2)`` the figure's pixels at ``judge``'s size, denser than ``fine``: they draw the
        copies of the region moves.
    rng : numpy.random.Generator
        Draws the random starts, one number of maps after another.
    seed : int
        Seeds the pixel samples and the chaos games.
    config : SearchConfig
        The settings.
    """

    coarse: Target
    fine: Target
    judge: Target
    copies: Copies
    covers: dict
    dense: np.ndarray
    rng: np.random.Generator
    seed: int
    config: SearchConfig


@dataclass(frozen=True)
class Row:
    """How one number of maps scores, at full precision.

    Attributes
    ----------
    maps : int
        The number of maps.
    cover : float
        Share of the figure the best set of copies covered at the search size.
    collage_px : float
        The maps' collage distance, pixels (at the refining size).
    chamfer_px : float
        Their attractor's symmetric Chamfer distance to the target at the refining size, pixels.
    iou : float
        Their attractor's IoU with the target at the judging size.
    score : float
        ``1 - iou + map_cost * maps``: the least is chosen.
    seconds : float
        Time spent on this number of maps.
    reoriented, grown : bool
        Whether its maps were turned (`reorient`), or are the fewer's and one more (`region_grow`).
    learned : bool
        Whether its maps are the learned guess's (`ifslib.learned.guess`), not the search's.
    regions, swapped : int
        Rounds of `region_swap` and of `swap` that replaced maps.
    """

    maps: int
    cover: float
    collage_px: float
    chamfer_px: float = float("nan")
    iou: float = float("nan")
    score: float = float("nan")
    seconds: float = 0.0
    reoriented: bool = False
    regions: int = 0
    grown: bool = False
    swapped: int = 0
    learned: bool = False

    def written(self) -> dict:
        """The row for the file: scores rounded to 4 digits, seconds to 2, the moves only where they apply."""
        out = {"maps": self.maps, "cover": round(self.cover, 4), "collage_px": round(self.collage_px, 4),
               "chamfer_px": round(self.chamfer_px, 4), "iou": round(self.iou, 4), "score": round(self.score, 4),
               "seconds": round(self.seconds, 2)}
        moves = {"reoriented": self.reoriented, "regions": self.regions, "grown": self.grown, "swapped": self.swapped,
                 "learned": self.learned}
        return out | {k: v for k, v in moves.items() if v}


@dataclass
class Board:
    """The rows of one search and the maps behind them.

    Attributes
    ----------
    context : Context
        What the search reads.
    rows : dict
        ``{k: Row}``, one per number of maps tried, in the order tried.
    found : dict
        ``{k: (k, 2, 3) maps}``, the maps behind each row.
    turned : list of int
        The numbers of maps reoriented (and grown): those the moves mend and the number of maps is chosen among.
    skipped, hopeless : list of int
        The numbers of maps not tried: they could not win by the Chamfer score, or the search gave up.
    """

    context: Context
    rows: dict[int, Row] = field(default_factory=dict)
    found: dict[int, np.ndarray] = field(default_factory=dict)
    turned: list[int] = field(default_factory=list)
    skipped: list[int] = field(default_factory=list)
    hopeless: list[int] = field(default_factory=list)

    @property
    def config(self) -> SearchConfig:
        """The search's settings (the context's)."""
        return self.context.config

    @property
    def table(self) -> list[Row]:
        """The rows in the order tried."""
        return list(self.rows.values())

    @property
    def turned_rows(self) -> list[Row]:
        """The rows reoriented (and grown), in the order they became so."""
        return [self.rows[k] for k in self.turned]

    def judge(self, row: Row, maps: np.ndarray, overlap: float | None = None, **changes) -> Row:
        """Keep ``maps`` ``(k, 2, 3)`` as the row's, with ``changes`` and their attractor's scores: the Chamfer
        distance at the refining size and the IoU at the judging size (``overlap``, when already drawn)."""
        k, config = len(maps), self.config
        self.found[k] = maps
        iou = attractor_iou(maps, self.context.judge, config=config) if overlap is None else overlap
        chamfer = attractor_chamfer(maps, self.context.fine, config=config)
        self.rows[k] = dataclasses.replace(row, chamfer_px=chamfer, iou=iou, score=choice_score(iou, k, config),
                                           **changes)
        return self.rows[k]

    def change(self, k: int, **changes) -> Row:
        """Row ``k`` with ``changes`` (not a new score)."""
        self.rows[k] = dataclasses.replace(self.rows[k], **changes)
        return self.rows[k]

    def add_time(self, k: int, t0: float) -> Row:
        """Add the seconds since ``t0`` (`time.perf_counter`) to row ``k``'s."""
        return self.change(k, seconds=self.rows[k].seconds + time.perf_counter() - t0)

    def chamfer_score(self, row: Row) -> float:
        """Which numbers of maps are tried and reoriented: the attractor's Chamfer distance plus a cost a map."""
        return trial_score(row.chamfer_px, row.maps, self.config)

    def declines(self, k: int) -> bool:
        """Whether ``k`` maps need not be tried (then recorded in `skipped` or `hopeless`)."""
        config, table = self.config, self.table
        if table and min(map(self.chamfer_score, table)) <= least_trial_score(k, config):
            self.skipped.append(k)  # k maps cannot score less: they cannot win by the Chamfer distance
            return True
        if k > config.give_up_maps and table and min(r.chamfer_px for r in table) > config.give_up_px:
            self.hopeless.append(k)
            return True
        return False

    def best(self, rows: list[Row] | None = None) -> Row:
        """The row of ``rows`` (by default the reoriented ones, else all) that scores least, the fewer maps on a tie."""
        return min(rows if rows is not None else self.turned_rows or self.table, key=_rank)

    def by_score(self, rows: list[Row]) -> list[Row]:
        """``rows`` from the least score, the fewer maps first on a tie."""
        return sorted(rows, key=_rank)

    def fits(self) -> bool:
        """Whether some reoriented number of maps draws an attractor of IoU ``swap_below`` or more."""
        return any(r.iou >= self.config.swap_below for r in self.turned_rows)

    def stuck(self) -> bool:
        """Whether some number of maps is reoriented (or grown), and none of them fits yet: the moves go on."""
        return bool(self.turned) and not self.fits()


def _rank(row: Row) -> tuple[float, int]:
    """A row's place in the choice: its score, then its number of maps (the fewer first)."""
    return row.score, row.maps
