"""Strategies: how a fit spends its steps over several single runs, a table `strategy` reads (extensions register
their own when imported). What each does: docs/guide/design.md."""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Callable, Protocol

import numpy as np
import torch

from ...errors import IFSError
from ..geometry.attractor import ATTRACTOR, is_attractor
from ..geometry.crossings import check_curve, is_curve
from ..geometry.ifs import IFS
from ...progress import note
from ..scoring.losses import loss_kind
from ..scoring.metrics import evaluate, self_crossings
from ...names import DEFAULT_STRATEGY, STRATEGIES  # the names live apart, for the command line to check without torch
from ..targets.placement import initialize
from ..targets.target import Target
from .options import Anneal, CoarseToFine, Multistart, Plain, Pyramid, Restart, RunOptions, Uncross
from .frame import Frame
from .pyramid import attractor_stage, climb, with_early_stop
from .result import FitResult


def check_strategy(strategy: str) -> str:
    """Return ``strategy`` if it is known, else raise `IFSError` naming the known ones."""
    if strategy not in STRATEGIES:
        raise IFSError(f"unknown strategy {strategy!r}; known strategies: {', '.join(STRATEGIES)}")
    return strategy


class Start(Protocol):
    """What an extension's start carries for the core: the IFS chosen without fitting (a plan's ``start``),
    which the strategies of one IFS fit, and the strategy that fits the whole start."""

    start: IFS
    strategy: str


#: ``run(frame, start, rng) -> FitResult``: the frame carries the run options and the strategy's own options object
Runner = Callable[["Frame", object, np.random.Generator], "FitResult"]


@dataclass(frozen=True)
class Strategy:
    """A strategy as the table holds it: its ``run(frame, start, rng)``, its ``options`` type, the start type it
    ``fits`` (an IFS, or a plan) and the ``refusal`` given another start."""

    run: Runner
    options: type
    fits: type = IFS
    refusal: str = ""


_TABLE: dict[str, Strategy] = {}


def register_strategy(name: str, strategy: Strategy) -> None:
    """Put ``strategy`` in the table under ``name``, one of `ifslib.names.STRATEGIES`."""
    _TABLE[check_strategy(name)] = strategy


def strategy(name: str) -> Strategy:
    """The table's entry for ``name``; an extension's strategy is in the table once its folder is imported."""
    if check_strategy(name) not in _TABLE:
        raise IFSError(f"strategy {name!r} belongs to an extension of ifslib that is not imported: import it first "
                       f"(import ifslib.splatting, import ifslib.automatic); in the table now: {', '.join(_TABLE)}")
    return _TABLE[name]


def resolve(chosen) -> tuple[str, object]:
    """A strategy given to `ifslib.fit` as its name (its options' defaults) or as its options object: the name and
    the options. Raise `IFSError` for anything else."""
    if isinstance(chosen, str):
        return chosen, strategy(chosen).options()
    for name, entry in _TABLE.items():
        if type(chosen) is entry.options:
            return name, chosen
    raise IFSError(f"strategy must be a name ({', '.join(STRATEGIES)}) or a strategy's options "
                   f"({', '.join(e.options.__name__ for e in _TABLE.values())}), got {type(chosen).__name__}")


def _split(steps: int, parts: int) -> list[int]:
    """``steps`` split into ``parts`` stages as evenly as possible (the first ones one longer)."""
    return [steps // parts + (i < steps % parts) for i in range(parts)]


def _best_of(results: list[FitResult], total_cost: int) -> FitResult:
    """The result with the lowest best loss, its history's cost the strategy's whole cost."""
    best = min(results, key=lambda r: r.best_loss)
    best.history.cost = total_cost
    return best


def _crosses(ifs: IFS) -> bool:
    if any(p.kind != "segment" for p in ifs.primitives):
        return False
    try:
        return self_crossings(ifs) > 0
    except IFSError:
        return True


def starts(ifs: IFS, target: Target, n: int, jitter: float, rng: np.random.Generator) -> list[IFS]:
    """``n`` starting points: ``ifs``, then jittered copies and, for curves, every other one a best-fit-line start
    (`initialize`): the first exactly on the line, the start that recovers most often (docs/results/strategies.md)."""
    out = [ifs]
    for k in range(1, n):
        if is_curve(ifs) and k % 2 == 1:
            line = initialize(ifs, target, jitter=0.0 if k == 1 else jitter, seed=int(rng.integers(2**31)))
            if k == 1 and torch.allclose(line.points, ifs.points):  # the given start is the line itself
                line = initialize(ifs, target, jitter=jitter, seed=int(rng.integers(2**31)))
            out.append(line)
        else:
            out.append(ifs.jittered(jitter, rng))
    return out


def _pyramid(frame: Frame, ifs: IFS, rng: np.random.Generator) -> FitResult:
    """The ``pyramid`` strategy (docs/guide/design.md)."""
    s, target = frame.settings, frame.target
    options = with_early_stop(frame.options, s)
    final = s.end_on_attractor and not is_attractor(options.depth)
    tried: list[tuple[FitResult, float]] = []
    stages, cost = [], 0
    for k, start in enumerate(starts(ifs, target, s.n_starts, s.jitter, rng)):
        label = f"start {k + 1}/{s.n_starts}"
        result, climbed = climb(frame, start, options, label)
        if final:
            result, stage = attractor_stage(frame, result.best, options, label)
            climbed.append(stage)
        cost += sum(st.steps for st in climbed)
        for st in climbed:
            st.start = k
        stages += climbed
        # judged on the full-size target, after the last stage only: a start far off at 64² can still
        # recover at full size; what is judged is the attractor when the fit ends on it
        chamfer = evaluate(result.best, target, depth=ATTRACTOR if final else None, attractor=False)["chamfer"]
        stages[-1].chamfer = chamfer
        tried.append((result, chamfer))
        if chamfer <= s.success:
            break
        if frame.progress:
            note(f"start {k + 1}/{s.n_starts}: Chamfer {chamfer:.2f} px > {s.success:g} px, trying the next start")
    best, chamfer = min(tried, key=lambda rc: rc[1])  # Chamfer at the full size: comparable across stages
    h = best.history
    h.cost, h.stages, h.starts_tried, h.chamfer = cost, stages, len(tried), chamfer
    h.recovered, h.judged = chamfer <= s.success, ATTRACTOR if final else "depth"
    return best


def _multistart(frame: Frame, ifs: IFS, rng: np.random.Generator) -> FitResult:
    s, n = frame.settings, frame.target.size
    n_probe = max(1, int(round(s.probe * frame.steps)))
    probes = [frame.run(c, n_probe, desc=f"probe {k + 1}/{s.n_starts} · {n}²")
              for k, c in enumerate(starts(ifs, frame.target, s.n_starts, s.jitter, rng))]
    order = sorted(range(len(probes)), key=lambda i: (_crosses(probes[i].best), probes[i].best_loss))
    finals = [frame.run(probes[i].best, frame.steps - n_probe, desc=f"continue {j + 1}/{s.keep} · {n}²")
              for j, i in enumerate(order[:s.keep])]
    return _best_of(finals, sum(r.history.cost for r in probes + finals))


def _restart(frame: Frame, ifs: IFS, rng: np.random.Generator) -> FitResult:
    s = frame.settings
    window, limit = max(1, frame.steps // 3), int(s.budget * frame.steps)
    spent, current, results = 0, ifs, []
    while spent < limit:
        results.append(frame.run(current, min(window, limit - spent)))
        spent += results[-1].history.cost
        best = min(results, key=lambda r: r.best_loss).best
        if evaluate(best, frame.target, attractor=False)["chamfer"] <= s.success:
            break
        last = results[-1].history.loss
        improving = len(last) > 10 and min(last[-len(last) // 4:]) < 0.99 * min(last[:len(last) // 2])
        current = results[-1].best if improving else best.jittered(s.jitter, rng)
    return _best_of(results, spent)


def _in_stages(frame: Frame, ifs: IFS, stages: list[dict], steps: list[int]) -> FitResult:
    """Runs one after another, each from the last one's best points, with the options changed by each of ``stages``."""
    current, results = ifs, []
    for changes, n in zip(stages, steps):
        results.append(frame.run(current, n, **changes))
        current = results[-1].best
    result = results[-1]
    result.history.cost = sum(r.history.cost for r in results)
    return result


def _anneal(frame: Frame, ifs: IFS) -> FitResult:
    loss, size = frame.options.loss, frame.target.size
    if isinstance(loss, str) and loss_kind(loss).family.sharpens == "sigma":
        stages = [{"sigma": 2.0 ** (3 - stage) / size} for stage in range(4)]
    else:
        stages = [{"levels": frame.options.levels + 3 - stage} for stage in range(4)]
    return _in_stages(frame, ifs, stages, _split(frame.steps, 4))


def run_strategy(name: str, start: IFS | Start, target: Target, *, steps: int, seed: int = 0,
                 options: RunOptions = RunOptions(), settings: object | None = None,
                 progress: bool = True, callback: Callable | None = None) -> FitResult:
    """Run the strategy ``name`` from ``start``: the public `ifslib.fit` below its checks. ``settings`` is the strategy's
    options object (its defaults when None); ``history.cost`` counts the steps of all runs."""
    entry = strategy(name)
    settings = entry.options() if settings is None else settings
    if entry.fits is IFS and not isinstance(start, IFS):
        start = start.start
    if not isinstance(start, entry.fits):
        raise IFSError(entry.refusal or f"strategy {name!r} fits a {entry.fits.__name__}, not a {type(start).__name__}")
    frame = Frame(target, steps, seed, options=options, progress=progress, callback=callback, settings=settings)
    result = entry.run(frame, start, np.random.default_rng(seed))
    result.history.strategy = name
    if not math.isfinite(result.best_loss):
        raise IFSError(f"strategy {name!r} found no finite loss")
    return result.record()  # what a saved fit records of how it was found


def _of_one_ifs(body: Runner, options: type) -> Strategy:
    """A strategy of one pattern: its runs at the options' depth, or the start's."""
    def run(frame: Frame, ifs: IFS, rng: np.random.Generator) -> FitResult:
        depth = frame.options.depth or ifs.depth
        return body(dataclasses.replace(frame, options=frame.options.replace(depth=depth)), ifs, rng)
    return Strategy(run, options)


def _uncross(frame: Frame, ifs: IFS) -> FitResult:
    check_curve(ifs, "strategy 'uncross'")
    return frame.run(ifs, frame.steps, crossing_weight=frame.options.crossing_weight or frame.settings.weight)


def _coarse_to_fine(frame: Frame, ifs: IFS) -> FitResult:
    depths = list(range(1, frame.options.depth + 1))
    return _in_stages(frame, ifs, [{"depth": d} for d in depths], _split(frame.steps, len(depths)))


for _name, (_body, _options) in {
    "pyramid": (_pyramid, Pyramid),
    "plain": (lambda frame, ifs, rng: frame.run(ifs, frame.steps), Plain),
    "uncross": (lambda frame, ifs, rng: _uncross(frame, ifs), Uncross),
    "coarse_to_fine": (lambda frame, ifs, rng: _coarse_to_fine(frame, ifs), CoarseToFine),
    "multistart": (_multistart, Multistart),
    "restart": (_restart, Restart),
    "anneal": (lambda frame, ifs, rng: _anneal(frame, ifs), Anneal),
}.items():
    register_strategy(_name, _of_one_ifs(_body, _options))
