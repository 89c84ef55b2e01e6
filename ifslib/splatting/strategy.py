"""The ``splat`` strategy: `fit_splat` from the start's maps and probabilities, registered in the core's table.

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
import torch

from ..errors import IFSError, LeafBudgetError, check_int
from ..names import DEFAULT_LR
from ..core.fitting.frame import Frame
from ..core.fitting.options import Pyramid, RunOptions
from ..core.fitting.pyramid import attractor_method
from ..core.fitting.result import FitResult, History
from ..core.fitting.strategies import Strategy, register_strategy
from ..core.geometry import patterns
from ..core.geometry.attractor import is_attractor
from ..core.geometry.crossings import is_curve
from ..core.geometry.ifs import IFS
from ..core.raster.distance import distance_field, resolve_device
from ..core.scoring.losses import loss
from ..progress import note
from .fit import SplatFitOptions, fit_splat

#: The splat fit's learning rates at ``lr`` = `ifslib.names.DEFAULT_LR`; another ``lr`` scales both alike.
BASE = SplatFitOptions()

#: The most ``lr`` may scale the splat fit's rates: 100 times its tuned 0.03 moves a map's angles by radians a step.
MAX_LR_SCALE = 100


def splat_options(frame: Frame, options: RunOptions) -> SplatFitOptions:
    """The splat fit's options for a run: the frame's budget, seed and progress, the run's device, and the learning
    rates scaled by ``options.lr / DEFAULT_LR`` (the splat fit's raw parameters are angles, logits and translations,
    not control points: its own rates are tuned for them, `ifslib.splatting.config`)."""
    scale = options.lr / DEFAULT_LR
    if scale > MAX_LR_SCALE:
        raise IFSError(f"strategy 'splat' scales its learning rates by lr / {DEFAULT_LR:g}, at most {MAX_LR_SCALE} "
                       f"times: give an lr of at most {MAX_LR_SCALE * DEFAULT_LR:g}, not {options.lr:g}")
    return SplatFitOptions(steps=frame.steps, seed=frame.seed, progress=frame.progress, kind="support",
                           device=splat_device(options), map_lr=BASE.map_lr * scale,
                           probability_lr=BASE.probability_lr * scale)


def splat_device(options: RunOptions) -> str:
    """Where the splat fit of a run goes: the run's device when it is the CPU or CUDA, else the CPU."""
    device = resolve_device(options.device).type
    return device if device in ("cpu", "cuda") else "cpu"


def check_start(ifs: IFS) -> torch.Tensor:
    """The start's ``(m, 3, 3)`` float64 maps, or `IFSError` when a map cannot be built or does not contract."""
    try:
        maps = ifs.to(torch.float64).maps().detach()
    except IFSError as exc:
        raise IFSError(f"strategy 'splat' starts from the start's maps, and they cannot be built: {exc}") from exc
    scales = torch.linalg.svdvals(maps[:, :2, :2])[:, 0]
    bad = [f"T{i + 1} (scale {float(s):.3g})" for i, s in enumerate(scales) if not float(s) < 1]
    if bad:
        raise IFSError(f"strategy 'splat' starts from maps that contract, and {', '.join(bad)} do(es) not: "
                       "shrink them, or start from ifslib.discover(target)")
    return maps


def scored_loss(ifs: IFS, frame: Frame, options: RunOptions, depth) -> float:
    """The run's loss of ``ifs`` drawn at ``depth`` on the target (an attractor whose certified cut outgrows the
    strategy's leaf budget is drawn from sampled leaves, as the attractor stage draws it)."""
    size = frame.target.size
    method = attractor_method(ifs, size, frame.settings.max_leaves) if is_attractor(depth) else options.method
    with torch.no_grad():
        try:
            field = distance_field(ifs, size, depth, method, device=options.device, gradient=options.gradient)
        except LeafBudgetError:
            field = distance_field(ifs, size, depth, "sampled", device=options.device)
        return float(loss(field, frame.target, options.loss, options.sigma, options.levels))


def fitted_ifs(maps: torch.Tensor, probabilities, start: IFS) -> IFS:
    """The fitted maps as affine rules at the start's depth and precision, drawn with segments for a curve's start
    (boxes otherwise), with the fitted probabilities."""
    ifs = patterns.affine(maps, depth=start.depth, primitive="segment" if is_curve(start) else "box",
                          name="splat", dtype=start.points.dtype)
    ifs.probabilities = tuple(probabilities)
    return ifs


@dataclass(frozen=True)
class Splat:
    """The ``splat`` strategy's options (its fit's own are `ifslib.splatting.SplatFitOptions`, set from the run's).

    Attributes
    ----------
    max_leaves : int
        The start and the fitted maps are scored on the certified cut of their attractor when it has at most
        this many leaves, else on sampled leaves (as the pyramid's attractor stage, `Pyramid.max_leaves`).
    """

    max_leaves: int = Pyramid.max_leaves

    def __post_init__(self) -> None:
        check_int(self.max_leaves, "max_leaves", 1)


def run_splat(frame: Frame, start: IFS, rng: np.random.Generator) -> FitResult:
    """The ``splat`` strategy as the core's table runs it (see the module docstring; ``rng`` is not used: the frame's
    seed seeds the splat fit)."""
    check_start(start)
    options = frame.options
    depth = start.depth if options.depth is None else options.depth
    t0 = time.perf_counter()
    fit = fit_splat(frame.target, maps=len(start.rules), start=start, options=splat_options(frame, options))
    result = fitted_ifs(fit.ifs.maps().detach(), fit.ifs.probabilities, start)
    before = scored_loss(start, frame, options, depth)
    try:
        after, why = scored_loss(result, frame, options, depth), None
    except IFSError as exc:  # a fitted map flat enough that the drawing at a depth refuses it
        after, why = math.inf, f"the fitted maps cannot be drawn at depth {depth} ({exc}): the start kept"
    kept = comparison(before, after, why, options, frame.target.size, depth)
    best = start.clone() if kept["kept"] == "start" else result
    for ifs in (best, result):
        ifs.meta["splat"] = dict(kept, maps=len(start.rules), steps=len(fit.losses))
    if frame.progress and kept["kept"] == "start":
        note(f"splat: {kept['why']}")
    steps = len(fit.losses)
    if frame.callback is not None:  # once, at the end: the splat fit's steps move no control points of the start
        frame.callback(steps - 1, min(before, after), best)
    history = History(step=list(range(steps)), loss=list(fit.losses), cost=steps,
                      seconds=[(time.perf_counter() - t0) / steps] * steps,
                      judged="attractor" if is_attractor(depth) else "depth")
    return FitResult(best=best, final=result, history=history, best_loss=min(before, after),
                     best_step=steps - 1 if best is result else 0)


def comparison(before: float, after: float, why: str | None, options: RunOptions, size: int, depth) -> dict:
    """What the strategy compared: the run's loss of the start and of the fitted maps at ``depth``, which is kept
    (the lower; the start on a tie) and, when it is the start, why."""
    name = options.loss if isinstance(options.loss, str) else "custom"
    out = {"loss": name, "depth": depth, "start_loss": before, "fitted_loss": after if math.isfinite(after) else None,
           "kept": "start" if before <= after else "fitted"}
    if out["kept"] == "start":
        out["why"] = why or (f"the fitted maps' {name} loss {after:.4g} is not below the start's {before:.4g} at "
                             f"{size}²: the start kept")
    return out


register_strategy("splat", Strategy(run_splat, Splat, refusal="strategy 'splat' fits an IFS (or a plan's start): give "
                                                       "ifslib.fit an IFS whose maps contract"))
