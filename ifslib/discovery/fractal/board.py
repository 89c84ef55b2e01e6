"""The scoreboard of one search: a row per number of maps tried, the maps found, and how they score.

A row is a dict of `SearchResult.table`: ``maps``, ``cover``, ``collage_px``, ``chamfer_px``,
``iou``, ``score``, ``seconds``, then ``reoriented``, ``regions``, ``grown`` and ``swapped`` where
they apply. `Context` is what every step of the search reads and none changes.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ...targets.target import Target
from .candidates import Copies
from .config import SearchConfig
from .judge import attractor_chamfer, attractor_iou


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


@dataclass
class Board:
    """The rows of one search and the maps behind them.

    Attributes
    ----------
    context : Context
        What the search reads.
    table : list of dict
        One row per number of maps tried, in the order tried.
    found : dict
        ``{k: (k, 2, 3) maps}``, the maps behind each row.
    overlaps : dict
        ``{k: float}``, each row's attractor IoU at the judging size, unrounded (what a move starts from).
    turned : list of dict
        The rows reoriented (and grown): those the moves mend and the number of maps is chosen among.
    skipped, hopeless : list of int
        The numbers of maps not tried: they could not win by the Chamfer score, or the search gave up.
    """

    context: Context
    table: list[dict] = field(default_factory=list)
    found: dict[int, np.ndarray] = field(default_factory=dict)
    overlaps: dict[int, float] = field(default_factory=dict)
    turned: list[dict] = field(default_factory=list)
    skipped: list[int] = field(default_factory=list)
    hopeless: list[int] = field(default_factory=list)

    @property
    def config(self) -> SearchConfig:
        """The search's settings (the context's)."""
        return self.context.config

    def judge(self, row: dict, maps: np.ndarray, overlap: float | None = None) -> None:
        """Keep ``maps`` ``(k, 2, 3)`` as row ``row``'s, with their attractor's scores: the Chamfer distance at
        the refining size and the IoU at the judging size (``overlap``, when already drawn)."""
        k, config = len(maps), self.config
        self.found[k] = maps
        self.overlaps[k] = attractor_iou(maps, self.context.judge, config=config) if overlap is None else overlap
        overlap = round(self.overlaps[k], 4)
        row.update({"chamfer_px": round(attractor_chamfer(maps, self.context.fine, config=config), 4),
                    "iou": overlap, "score": round(1 - overlap + config.map_cost * k, 4)})

    def chamfer_score(self, row: dict) -> float:
        """Which numbers of maps are tried and reoriented: the attractor's Chamfer distance plus a cost a map."""
        return row["chamfer_px"] + self.config.chamfer_cost * row["maps"]

    def declines(self, k: int) -> bool:
        """Whether ``k`` maps need not be tried (then recorded in `skipped` or `hopeless`)."""
        config = self.config
        if self.table and min(map(self.chamfer_score, self.table)) <= config.chamfer_cost * k:
            self.skipped.append(k)  # k maps score at least chamfer_cost * k: they cannot win by the Chamfer distance
            return True
        if k > config.give_up_maps and self.table and min(r["chamfer_px"] for r in self.table) > config.give_up_px:
            self.hopeless.append(k)
            return True
        return False

    def row(self, k: int) -> dict | None:
        """The row of ``k`` maps, or None when ``k`` was not tried."""
        return next((r for r in self.table if r["maps"] == k), None)

    def best(self, rows: list[dict] | None = None) -> dict:
        """The row of ``rows`` (by default the reoriented ones, else all) that scores least, the fewer maps on a tie."""
        return min(rows if rows is not None else self.turned or self.table, key=_rank)

    def by_score(self, rows: list[dict]) -> list[dict]:
        """``rows`` from the least score, the fewer maps first on a tie."""
        return sorted(rows, key=_rank)

    def fits(self) -> bool:
        """Whether some reoriented number of maps draws an attractor of IoU ``swap_below`` or more."""
        return any(r["iou"] >= self.config.swap_below for r in self.turned)

    def stuck(self) -> bool:
        """Whether some number of maps is reoriented (or grown), and none of them fits yet: the moves go on."""
        return bool(self.turned) and not self.fits()

    @staticmethod
    def add_time(row: dict, t0: float) -> None:
        """Add the seconds since ``t0`` (`time.perf_counter`) to the row's."""
        row["seconds"] = round(row["seconds"] + time.perf_counter() - t0, 2)


def _rank(row: dict) -> tuple[float, int]:
    """A row's place in the choice: its score, then its number of maps (the fewer first)."""
    return row["score"], row["maps"]
