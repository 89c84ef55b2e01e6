"""The ``auto`` strategy: a plan read from the image (`ifslib.automatic.plan.Plan`) fitted by
comparing its candidates, coarse to fine (`ifslib.core.fitting.pyramid`).

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass

from ..errors import IFSError
from .config import AUTO
from .plan import Plan
from ..core.geometry.attractor import ATTRACTOR
from ..core.scoring.metrics import evaluate
from .choice import AutoRun, Candidate, Kind
from ..core.fitting.options import Pyramid, RunOptions
from ..core.fitting.frame import Frame
from ..core.fitting.pyramid import attractor_stage, climb, with_early_stop
from ..core.fitting.result import FitResult, Stage
from ..core.fitting.strategies import Strategy, register_strategy

#: The section of `ifslib.automatic.config.AUTO` this module reads: its tuned numbers, each with what it trades.
FIT = AUTO.fit


def fit_plan(plan: Plan, frame: Frame, options: RunOptions, *, end_on_attractor: bool = True) -> FitResult:
    """Fit ``plan`` (see the module docstring); ``history.auto`` (an `ifslib.automatic.choice.AutoRun`) holds the
    candidates compared and the one chosen.

    The fitted IFSs' ``meta["pattern"]`` is the chosen candidate's description with ``chosen``; for a
    plan with rivals also ``decision``, which kind was kept and why.
    """
    if options.depth not in (None, plan.depth):
        raise IFSError("an automatic start's candidates have depths of their own: fix the depth with "
                       "ifslib.discover(target, depth=...)")
    options = with_early_stop(options.replace(depth=None), frame.settings)
    if plan.rivals:
        results, ious = zip(*(_fit_one(p, frame, options, end_on_attractor) for p in (plan, *plan.rivals)))
        return choose_kind(list(results), frame, why=plan.why, ious=list(ious))
    return _fit_one(plan, frame, options, end_on_attractor)[0]


def choose_kind(results: list[FitResult], frame: Frame, *, why: str | None = None,
                ious: list[float | None] | None = None) -> FitResult:
    """Of the fits of one figure as different kinds, the one whose attractor scores least: 1 - attractor IoU
    at the target's size plus `FIT.kind_map_cost` a map. Its history counts every fit's steps, and says in
    ``auto.kinds`` and ``auto.decision`` (and its IFSs' ``meta["pattern"]["decision"]``) what was compared,
    after ``why`` (why both kinds were fitted) when given. ``ious`` are the fits' attractor IoUs at the target's
    size where already measured (None where not): each is measured once."""
    kinds = []
    for result, known in zip(results, ious or [None] * len(results)):
        iou = evaluate(result.best, frame.target, depth=ATTRACTOR)["iou"] if known is None else known
        kinds.append(Kind(result.history.auto.kind, len(result.best.rules), iou, result.history.cost))
    best = min(range(len(kinds)), key=lambda i: (kinds[i].score, kinds[i].maps))  # full precision decides
    rows = [k.written() for k in kinds]  # what the file and the history say
    decision = (f"{rows[best]['kind']} kept: " + "; ".join(
        f"{r['kind']} of {r['maps']} maps, attractor IoU {r['attractor_iou']:.3f}, score {r['score']:.3f}" for r in rows)
        + f" (1 - attractor IoU at {frame.target.size}² plus {FIT.kind_map_cost:g} a map, the least kept)")
    if why:
        decision = f"{why}; {decision}"
    result = results[best]
    result.history.cost = sum(k.steps for k in kinds)
    result.history.auto = dataclasses.replace(result.history.auto, kinds=tuple(kinds), decision=decision)
    for ifs in (result.best, result.final):
        ifs.meta["pattern"] = result.history.auto.described()
    return result


def _fit_one(plan: Plan, frame: Frame, options: RunOptions, end_on_attractor: bool) -> tuple[FitResult, float | None]:
    """Fit one kind's plan: a fractal's maps, or the candidates of a curve or a shape compared by their loss; with
    the fit's attractor IoU at the target's size when it was measured on the way (a fractal's), else None."""
    if plan.kind == "fractal":
        return _fit_fractal(plan, frame, options, end_on_attractor)
    tried = [_probe(frame, candidate, options) for candidate in plan.candidates]
    # the lowest loss after the same number of steps; fewer maps win a tie
    winner, chosen = min(tried, key=lambda rc: (rc[1].value, rc[1].maps))
    label = f"{chosen.maps} maps"
    options = options.replace(depth=chosen.depth)
    result, stages = climb(frame, winner.best, options, label)
    shape = plan.kind == "shape"
    if shape and options.loss != FIT.polish_loss and not end_on_attractor:
        # The distance loss brings the copies over the figure from afar, but it hardly sees the
        # one-pixel slivers left between them; the pixel loss counts each uncovered pixel fully.
        target = frame.target
        result = frame.run(result.best, min(frame.steps, frame.settings.stage_steps), options.replace(loss=FIT.polish_loss),
                           desc=f"{label} · {target.size}² · {FIT.polish_loss}")
        stages.append(Stage(size=target.size, loss=FIT.polish_loss, steps=result.history.cost,
                            stopped=result.history.stopped, best_loss=result.best_loss))
    if end_on_attractor:
        result, stage = attractor_stage(frame, result.best, options.replace(loss=FIT.polish_loss) if shape else options,
                                        label, max_leaves=FIT.shape_max_leaves if shape else None)
        stages.append(stage)
    # the chosen candidate's own description is the file's (it decides nothing here)
    run = AutoRun(plan.kind, chosen.maps, tuple(c for _, c in tried), dict(winner.best.meta["pattern"]))
    cost = sum(c.steps for _, c in tried) + sum(s.steps for s in stages)
    return _finish(result, run, stages, cost), None


def _probe(frame: Frame, candidate, options: RunOptions) -> tuple[FitResult, Candidate]:
    """A candidate fitted at the coarsest size for `FIT.probe_steps` steps, and its row in ``history.auto``."""
    k, coarse = len(candidate.rules), frame.sizes[0]
    t0 = time.perf_counter()
    result = frame.run(candidate, min(frame.steps, FIT.probe_steps),
                       options.replace(stage_lr=options.lr * frame.target.size / coarse), target=frame.levels[coarse],
                       desc=f"{k} maps, depth {candidate.depth} · {coarse}²")
    return result, Candidate(k, candidate.depth, "loss", result.best_loss, result.history.cost,
                             time.perf_counter() - t0)


def _fit_fractal(plan: Plan, frame: Frame, options: RunOptions,
                 end_on_attractor: bool) -> tuple[FitResult, float | None]:
    """A fractal's plan: its maps were found by the search, so only the attractor stage is left (at most
    `FIT.fractal_stage_steps` steps), or, without ``end_on_attractor``, a run of the drawing at its depth; with the
    attractor IoU of what is returned, when measured (`_no_worse_than_start`)."""
    start = plan.start
    label = f"{len(start.rules)} maps"
    budget = min(frame.steps, FIT.fractal_stage_steps)
    iou = None
    if end_on_attractor:
        result, stage = attractor_stage(frame, start, options.replace(loss=FIT.fractal_loss), label, steps=budget)
        result, iou = _no_worse_than_start(start, result, frame, stage)
        stages = [stage]
        if iou < FIT.splat_below:
            result, iou, polish = _splat_polish(result, iou, frame, options)
            stages.append(polish)
    else:
        result = frame.run(start, budget, options.replace(depth=start.depth), desc=f"{label} · {frame.target.size}²")
        stages = [Stage(size=frame.target.size, steps=result.history.cost, stopped=result.history.stopped,
                        best_loss=result.best_loss)]
    searched = tuple(Candidate(row.maps, start.depth, "learned score" if row.learned else "score", row.score, 0,
                               row.seconds) for row in plan.search)
    run = AutoRun(plan.kind, len(start.rules), searched, dict(plan.pattern))
    return _finish(result, run, stages, sum(s.steps for s in stages)), iou


def _splat_polish(result: FitResult, iou: float, frame: Frame,
                  options: RunOptions) -> tuple[FitResult, float, Stage]:
    """A fractal's fit whose attractor falls short (IoU ``iou`` below `FIT.splat_below`) polished by the splat fit
    (`ifslib.splatting.fit_splat`: every map and probability at once, on the chaos game's coverage at the target's
    size, without annealing or reselection, at `FIT.splat_lr`); the polished maps are returned when their
    attractor's IoU at the target's size is higher, else ``result``, and the stage says which.

    The attractor stage moves maps by the gradient of drawn leaves, one pixel loss; the splat fit sees every map's
    share of the figure through the chaos game's points, and the probabilities with them.
    """
    from ..splatting.fit import SplatFitOptions, fit_splat
    from ..splatting.strategy import fitted_ifs, scored_loss, splat_device

    start = result.best
    fit = fit_splat(frame.target, start=start, options=SplatFitOptions(
        steps=min(frame.steps, FIT.splat_steps), map_lr=FIT.splat_lr, anneal_noise=0.0, reseed_every=0,
        seed=frame.seed, kind="support", coarse_to_fine=False, device=splat_device(options), progress=frame.progress))
    polished = fitted_ifs(fit.ifs.maps().detach(), fit.ifs.probabilities, start)
    after = evaluate(polished, frame.target, depth=ATTRACTOR)["iou"]
    stage = Stage(size=frame.target.size, steps=len(fit.losses), stopped="steps", best_loss=fit.losses[-1],
                  depth=ATTRACTOR, method="splat", loss="coverage")
    if after <= iou:
        stage.kept_start = (f"the splat fit's attractor IoU {after:.3f} is not above the stage's {iou:.3f} at "
                            f"{frame.target.size}²: the stage's maps kept")
        return result, iou, stage
    # the run's own loss of the polished attractor, so that best_loss stays the loss the history is in
    best_loss = scored_loss(polished, frame, options.replace(loss=FIT.fractal_loss), ATTRACTOR)
    return FitResult(best=polished, final=polished, history=result.history, best_loss=best_loss,
                     best_step=result.best_step), after, stage


def _no_worse_than_start(start, result: FitResult, frame: Frame, stage: Stage) -> tuple[FitResult, float]:
    """The stage's result, or its start when the start's attractor has the higher IoU at the target's size; and
    the IoU of the one returned.

    The stage minimises a loss of a drawing of the attractor, which is not its IoU: on a solid figure of
    overlapping copies (the overlap class of `benchmarks/samplers.py`) the pixel loss of sampled
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


def _finish(result: FitResult, run: AutoRun, stages: list[Stage], cost: int) -> FitResult:
    """The history's account of the choice (``run``), and the fitted IFSs' description for the file, written from it."""
    for stage in stages:
        stage.maps = run.chosen
    h = result.history
    h.cost, h.stages, h.kind, h.auto = cost, stages, run.kind, run
    for ifs in (result.best, result.final):
        ifs.meta["pattern"] = run.described()
    return result


@dataclass(frozen=True)
class Auto(Pyramid):
    """The ``auto`` strategy's options: the pyramid's, whose stages its chosen candidate climbs."""


def _run(frame: Frame, plan: Plan, rng) -> FitResult:
    """The ``auto`` strategy as the core's table runs it (the generator is not used: the plan holds its seeds)."""
    return fit_plan(plan, frame, frame.options, end_on_attractor=frame.settings.end_on_attractor)


register_strategy("auto", Strategy(_run, Auto, fits=Plan, refusal="strategy 'auto' fits an automatic start, a plan read "
                                                             "from the image: use ifslib.discover(target)"))
