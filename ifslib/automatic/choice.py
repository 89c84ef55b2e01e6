"""The automatic fit's typed record: `AutoRun` (what was compared and chosen), its `Candidate` rows and, for a
figure fitted as two kinds, the `Kind` rows.

Decisions read these records at full precision; ``history.auto`` and the fitted IFSs' ``meta["pattern"]`` are
written from them once (`AutoRun.written`), for the file.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from .config import AUTO


@dataclass(frozen=True)
class Candidate:
    """One start the automatic path compared, in one layout for every kind.

    Attributes
    ----------
    maps, depth : int
        Its number of maps and its depth.
    by : str
        What it was compared by: ``"loss"`` (a curve's or a shape's loss after ``AUTO.fit.probe_steps`` steps at
        the coarsest size) or ``"score"`` (the fractal search's ``1 - attractor IoU + map_cost * maps``; ``"learned
        score"`` for the learned guess's row, scored alike).
    value : float
        That loss or score, full precision: the least wins (fewer maps on a tie).
    steps : int
        Fit steps spent on it (0 for the search's rows: the search spends none of the fit's).
    seconds : float
        Time spent on it (for a search row, the search's time on that number of maps).
    """

    maps: int
    depth: int
    by: str
    value: float
    steps: int
    seconds: float

    def written(self) -> dict:
        """The row for ``history.auto["candidates"]``."""
        return dataclasses.asdict(self)


@dataclass(frozen=True)
class Kind:
    """One kind's fit of an ambiguous figure, as `ifslib.automatic.fit_plan.choose_kind` compares them: its number of
    maps, its attractor's IoU at the target's size (full precision) and the steps it spent."""

    kind: str
    maps: int
    attractor_iou: float
    steps: int

    @property
    def score(self) -> float:
        """1 - attractor IoU plus ``AUTO.fit.kind_map_cost`` a map: the least is kept."""
        return 1 - self.attractor_iou + AUTO.fit.kind_map_cost * self.maps

    def written(self) -> dict:
        """The row for the history and the file, rounded to 4 digits."""
        return {"kind": self.kind, "maps": self.maps, "attractor_iou": round(self.attractor_iou, 4),
                "score": round(self.score, 4), "steps": self.steps}


@dataclass(frozen=True)
class AutoRun:
    """What the ``auto`` strategy compared and chose (``result.history.auto``).

    Attributes
    ----------
    kind : str
        The kind fitted: ``"curve"``, ``"shape"`` or ``"fractal"``.
    chosen : int
        The chosen number of maps.
    candidates : tuple of Candidate
        What was compared, in order.
    pattern : dict
        The chosen start's description as the file keeps it (for a fractal with the search's whole table,
        ``search``, which the history keeps and ``meta["pattern"]`` leaves out); it decides nothing.
    kinds : tuple of Kind
        For a figure fitted as a fractal and as a shape: both fits, as compared. Empty otherwise.
    decision : str, optional
        With ``kinds``: which kind was kept, and why, in words.
    """

    kind: str
    chosen: int
    candidates: tuple[Candidate, ...]
    pattern: dict
    kinds: tuple[Kind, ...] = ()
    decision: str | None = None

    def described(self) -> dict:
        """The fitted IFSs' ``meta["pattern"]``: the chosen start's description, ``chosen`` and any ``decision``."""
        out = {**{k: v for k, v in self.pattern.items() if k != "search"}, "chosen": self.chosen}
        return out if self.decision is None else {**out, "decision": self.decision}

    def written(self) -> dict:
        """``history.auto`` for the file: the pattern (with a fractal's ``search`` table), the ``candidates`` as rows,
        ``chosen``, and the ``kinds`` and ``decision`` where two kinds were fitted."""
        out = {**self.pattern, "candidates": [c.written() for c in self.candidates], "chosen": self.chosen}
        if self.kinds:
            out |= {"kinds": [k.written() for k in self.kinds], "decision": self.decision}
        return out
