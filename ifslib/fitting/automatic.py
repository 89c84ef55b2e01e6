"""The ``auto`` strategy: a plan read from the image (`ifslib.discovery.plan.Plan`) fitted by
comparing its candidates, coarse to fine (`ifslib.fitting.pyramid`).

Each candidate start is fitted at the coarsest size of the pyramid for the same number of steps
(`FIT.probe_steps`), and the one with the lowest loss goes on through the pyramid's stages; a
shape then gets a stage at full size with the pixel loss (`FIT.polish_loss`), which fills the slivers
between copies, or, ending on the attractor (the default), the attractor stage with that loss. A
fractal's plan (its maps and their number chosen by the search) goes straight to the attractor
stage (`FIT.fractal_stage_steps`, `FIT.fractal_loss`). A plan with rivals (a figure that may be a fractal
or a shape) has each of its kinds fitted so, and the one whose attractor scores best for its number
of maps is kept (`choose_kind`). The plan is taken as it is: nothing here calls discovery again.
"""
from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass

from ..errors import IFSError
from ..discovery.config import AUTO
from ..discovery.plan import Plan
from ..geometry.attractor import ATTRACTOR
from ..scoring.metrics import evaluate
from .options import RunOptions
from .frame import Frame
from .pyramid import FIT_MAX_LEAVES, PYRAMID_STAGE_STEPS, attractor_stage, climb, with_early_stop
from .result import FitResult, Stage

#: The section of `ifslib.discovery.config.AUTO` this module reads: its tuned numbers, each with what it trades.
FIT = AUTO.fit


@dataclass(frozen=True)
class Kind:
    """One kind's fit of an ambiguous figure, as `choose_kind` compares them: its number of maps, its attractor's
    IoU at the target's size (full precision) and the steps it spent."""

    kind: str
    maps: int
    attractor_iou: float
    steps: int

    @property
    def score(self) -> float:
        """1 - attractor IoU plus `FIT.kind_map_cost` a map: the least is kept."""
        return 1 - self.attractor_iou + FIT.kind_map_cost * self.maps

    def written(self) -> dict:
        """The row for the history and the file, rounded to 4 digits."""
        return {"kind": self.kind, "maps": self.maps, "attractor_iou": round(self.attractor_iou, 4),
                "score": round(self.score, 4), "steps": self.steps}


@dataclass(frozen=True)
class Probe:
    """A curve's or a shape's candidate after `FIT.probe_steps` steps at the coarsest size: the lowest ``loss``
    goes on (fewer maps on a tie)."""

    maps: int
    depth: int
    loss: float
    steps: int
    seconds: float

    def written(self) -> dict:
        """The row for ``history.auto["candidates"]``."""
        return dataclasses.asdict(self)


def fit_plan(plan: Plan, frame: Frame, options: RunOptions, *, end_on_attractor: bool = True) -> FitResult:
    """Fit ``plan`` (see the module docstring); ``history.auto`` lists the candidates and the one chosen.

    The fitted IFSs' ``meta["pattern"]`` is the chosen candidate's description with ``chosen``; for a
    plan with rivals also ``decision``, which kind was kept and why.
    """
    if options.depth not in (None, plan.depth):
        raise IFSError("an automatic start's candidates have depths of their own: fix the depth with "
                       "ifslib.initialize('auto', target, depth=...)")
    options = with_early_stop(options.replace(depth=None))
    if plan.rivals:
        results, ious = zip(*(_fit_one(p, frame, options, end_on_attractor) for p in (plan, *plan.rivals)))
        return choose_kind(list(results), frame, why=plan.pattern.get("ambiguous"), ious=list(ious))
    return _fit_one(plan, frame, options, end_on_attractor)[0]


def choose_kind(results: list[FitResult], frame: Frame, *, why: str | None = None,
                ious: list[float | None] | None = None) -> FitResult:
    """Of the fits of one figure as different kinds, the one whose attractor scores least: 1 - attractor IoU
    at the target's size plus `FIT.kind_map_cost` a map. Its history counts every fit's steps, and says in
    ``auto["kinds"]`` and ``auto["decision"]`` (and its IFSs' ``meta["pattern"]["decision"]``) what was compared,
    after ``why`` (why both kinds were fitted) when given. ``ious`` are the fits' attractor IoUs at the target's
    size where already measured (None where not): each is measured once."""
    kinds = []
    for result, known in zip(results, ious or [None] * len(results)):
        iou = evaluate(result.best, frame.target, depth=ATTRACTOR)["iou"] if known is None else known
        kinds.append(Kind(result.history.kind, len(result.best.rules), iou, result.history.cost))
    best = min(range(len(kinds)), key=lambda i: (kinds[i].score, kinds[i].maps))  # full precision decides
    rows = [k.written() for k in kinds]  # what the file and the history say
    decision = (f"{rows[best]['kind']} kept: " + "; ".join(
        f"{r['kind']} of {r['maps']} maps, attractor IoU {r['attractor_iou']:.3f}, score {r['score']:.3f}" for r in rows)
        + f" (1 - attractor IoU at {frame.target.size}² plus {FIT.kind_map_cost:g} a map, the least kept)")
    if why:
        decision = f"{why}; {decision}"
    result = results[best]
    result.history.cost = sum(r["steps"] for r in rows)
    result.history.auto = {**result.history.auto, "kinds": rows, "decision": decision}
    for ifs in (result.best, result.final):
        ifs.meta["pattern"] = {**ifs.meta["pattern"], "decision": decision}
    return result


def _fit_one(plan: Plan, frame: Frame, options: RunOptions, end_on_attractor: bool) -> tuple[FitResult, float | None]:
    """Fit one kind's plan: a fractal's maps, or the candidates of a curve or a shape compared by their loss; with
    the fit's attractor IoU at the target's size when it was measured on the way (a fractal's), else None."""
    if plan.kind == "fractal":
        return _fit_fractal(plan, frame, options, end_on_attractor)
    tried = [_probe(frame, candidate, options) for candidate in plan.candidates]
    # the lowest loss after the same number of steps; fewer maps win a tie
    winner, chosen = min(tried, key=lambda rc: (rc[1].loss, rc[1].maps))
    label = f"{chosen.maps} maps"
    options = options.replace(depth=chosen.depth)
    result, stages = climb(frame, winner.best, options, label)
    shape = plan.kind == "shape"
    if shape and options.loss != FIT.polish_loss and not end_on_attractor:
        # The distance loss brings the copies over the figure from afar, but it hardly sees the
        # one-pixel slivers left between them; the pixel loss counts each uncovered pixel fully.
        target = frame.target
        result = frame.run(result.best, min(frame.steps, PYRAMID_STAGE_STEPS), options.replace(loss=FIT.polish_loss),
                           desc=f"{label} · {target.size}² · {FIT.polish_loss}")
        stages.append(Stage(size=target.size, loss=FIT.polish_loss, steps=result.history.cost,
                            stopped=result.history.stopped, best_loss=result.best_loss))
    if end_on_attractor:
        result, stage = attractor_stage(frame, result.best, options.replace(loss=FIT.polish_loss) if shape else options,
                                        label, max_leaves=FIT.shape_max_leaves if shape else FIT_MAX_LEAVES)
        stages.append(stage)
    # the chosen candidate's own description, for the file (it decides nothing here)
    choice = {**winner.best.meta["pattern"], "candidates": [c.written() for _, c in tried], "chosen": chosen.maps}
    cost = sum(c.steps for _, c in tried) + sum(s.steps for s in stages)
    return _finish(result, plan.kind, choice, stages, cost), None


def _probe(frame: Frame, candidate, options: RunOptions) -> tuple[FitResult, Probe]:
    """A candidate fitted at the coarsest size for `FIT.probe_steps` steps, and its row in ``history.auto``."""
    k, coarse = len(candidate.rules), frame.sizes[0]
    t0 = time.perf_counter()
    result = frame.run(candidate, min(frame.steps, FIT.probe_steps),
                       options.replace(stage_lr=options.lr * frame.target.size / coarse), target=frame.levels[coarse],
                       desc=f"{k} maps, depth {candidate.depth} · {coarse}²")
    return result, Probe(k, candidate.depth, result.best_loss, result.history.cost, time.perf_counter() - t0)


def _fit_fractal(plan: Plan, frame: Frame, options: RunOptions,
                 end_on_attractor: bool) -> tuple[FitResult, float | None]:
    """A fractal's plan: its maps were found by the search, so only the attractor stage is left (at most
    `FIT.fractal_stage_steps` steps), or, without ``end_on_attractor``, a run of the drawing at its depth; with the
    attractor IoU of what is returned, when measured (`_no_worse_than_start`)."""
    pattern, start = plan.pattern, plan.start
    label = f"{pattern['maps']} maps"
    budget = min(frame.steps, FIT.fractal_stage_steps)
    iou = None
    if end_on_attractor:
        result, stage = attractor_stage(frame, start, options.replace(loss=FIT.fractal_loss), label, steps=budget)
        result, iou = _no_worse_than_start(start, result, frame, stage)
    else:
        result = frame.run(start, budget, options.replace(depth=start.depth), desc=f"{label} · {frame.target.size}²")
        stage = Stage(size=frame.target.size, steps=result.history.cost, stopped=result.history.stopped,
                      best_loss=result.best_loss)
    choice = {**{k: v for k, v in pattern.items() if k != "search"}, "candidates": pattern.get("search", []),
              "chosen": pattern["maps"]}
    return _finish(result, plan.kind, choice, [stage], stage.steps), iou


def _no_worse_than_start(start, result: FitResult, frame: Frame, stage: Stage) -> tuple[FitResult, float]:
    """The stage's result, or its start when the start's attractor has the higher IoU at the target's size; and
    the IoU of the one returned.

    The stage minimises a loss of a drawing of the attractor, which is not its IoU: on a solid figure of
    overlapping copies (`ifslib.geometry.samplers.literature_ifs`'s overlap class) the pixel loss of sampled
    leaves drew a map out to scale 0.99 and the attractor's IoU fell from 0.949 to 0.881
    (docs/results/literature.md). The search's maps were judged by that IoU; a fit must not return worse.
    """
    before = evaluate(start, frame.target, depth=ATTRACTOR)["iou"]
    after = evaluate(result.best, frame.target, depth=ATTRACTOR)["iou"]
    if after >= before:
        return result, after
    stage.kept_start = (f"the fitted attractor's IoU {after:.3f} is below the start's {before:.3f} at "
                        f"{frame.target.size}²: the start kept")
    loss = result.history.loss
    return FitResult(best=start.clone(), final=result.final, history=result.history,
                     best_loss=loss[0] if loss else result.best_loss, best_step=0), before  # the loss before step 0


def _finish(result: FitResult, kind: str, choice: dict, stages: list[Stage], cost: int) -> FitResult:
    """The history's account of the choice, and the fitted IFSs' description for the file."""
    for stage in stages:
        stage.maps = choice["chosen"]
    h = result.history
    h.cost, h.stages, h.kind, h.auto = cost, stages, kind, choice
    for ifs in (result.best, result.final):
        ifs.meta["pattern"] = {k: v for k, v in choice.items() if k != "candidates"}
    return result
