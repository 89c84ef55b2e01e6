"""What a fit returns: `FitResult`, its typed `History` (written into ``meta["history"]`` by `History.to_dict`,
a checkpoint's read back by `History.from_dict`), and the `Stage` records of a strategy."""
from __future__ import annotations

import copy
import dataclasses
import math
from dataclasses import dataclass, field
from typing import Protocol

from ..geometry.ifs import IFS


class Record(Protocol):
    """A strategy's own typed record of what it compared and chose (the automatic path's
    `ifslib.automatic.choice.AutoRun`); the file gets ``written()``."""

    def written(self) -> dict: ...


@dataclass
class Stage:
    """One run of a strategy: where it ran, how many steps it spent and why it stopped; the optional fields are set
    where they apply (``depth`` ``"attractor"`` for an attractor stage, ``chamfer`` for a start's last stage)."""

    size: int
    steps: int
    stopped: str
    best_loss: float
    start: int | None = None
    maps: int | None = None
    depth: int | str | None = None
    method: str | None = None
    loss: str | None = None
    chamfer: float | None = None
    fallback: str | None = None
    kept_start: str | None = None

    def to_dict(self) -> dict:
        """The set fields, in the JSON file's order (``start`` / ``maps`` first)."""
        order = ("start", "maps", "size", "depth", "method", "loss", "steps", "stopped", "best_loss", "chamfer",
                 "fallback", "kept_start")
        return {k: getattr(self, k) for k in order if getattr(self, k) is not None}


@dataclass
class History:
    """How a fit went: per step its index, loss and time; the rollbacks; why the returned run stopped; ``cost``, every
    step of every run; the strategy's stages and judgement; snapshots for `ifslib.animate`."""

    step: list[int] = field(default_factory=list)
    loss: list[float] = field(default_factory=list)
    seconds: list[float] = field(default_factory=list)
    rollbacks: list[dict] = field(default_factory=list)
    stopped: str = "steps"
    cost: int = 0
    strategy: str | None = None
    stages: list[Stage] = field(default_factory=list)
    starts_tried: int | None = None
    chamfer: float | None = None
    recovered: bool | None = None
    judged: str | None = None
    kind: str | None = None
    auto: Record | None = None
    snapshots: dict | None = None
    pattern: dict | None = None

    def to_dict(self) -> dict:
        """A JSON-ready copy: the per-step lists, then the fields that are set."""
        out = {}
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if f.name == "stages":
                if value:
                    out["stages"] = [s.to_dict() for s in value]
            elif f.name == "auto":
                if value is not None:
                    out["auto"] = copy.deepcopy(value.written())
            elif value is not None:
                out[f.name] = copy.deepcopy(value)
        return out

    @classmethod
    def from_dict(cls, saved: dict) -> History:
        """The history of a checkpoint (`to_dict`'s output, read back from JSON)."""
        names = {f.name for f in dataclasses.fields(cls)}
        # a checkpoint is of one plain run, which has no automatic record to read back
        values = {k: copy.deepcopy(v) for k, v in saved.items() if k in names and k != "auto"}
        values["stages"] = [Stage(**s) for s in saved.get("stages", [])]
        return cls(**values)


@dataclass
class FitResult:
    """What `ifslib.fit` returns: the ``best`` points (lowest loss seen), the ``final`` ones, the history, ``best_loss``
    and ``best_step``."""

    best: IFS
    final: IFS
    history: History = field(default_factory=History)
    best_loss: float = math.inf
    best_step: int = -1

    def record(self) -> FitResult:
        """Write the history into ``meta["history"]`` of ``best`` and ``final`` (what a saved fit keeps); returns self."""
        for ifs in (self.best, self.final):
            ifs.meta["history"] = self.history.to_dict()
        return self
