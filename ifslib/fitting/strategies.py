"""Strategies: how a fit spends its steps over several single runs (`ifslib.fitting.run.run`).

Each strategy calls `run` (never the public `ifslib.fit`, which sits above this module and picks a
strategy) and returns the best result. Every step of every run counts in ``history["cost"]``, so
strategies compare per step spent:

``pyramid``
    The default. Coarse to fine in pixels, and starts tried one after another until one recovers
    the target. Each start runs at the coarsest size of the target's pyramid (64² for a 256²
    target), then at each finer size (4 times larger, `PYRAMID_FACTOR`) up to the target's own,
    every stage ending when its loss has converged (``tol``, ``patience``). The learning rate
    grows with the pixel size (``lr * size / stage_size``), so a coarse step moves the points as
    far, in pixels, as a fine one.
    Each start then ends with a stage that fits its **attractor** at the full size
    (`attractor_stage`), and is judged by the attractor's symmetric Chamfer distance to the target;
    once it is at most ``success`` pixels, no more starts are tried. The starts are those of
    ``multistart``. Each stage spends at most ``min(steps, PYRAMID_STAGE_STEPS)`` steps (the
    attractor's, `ATTRACTOR_STAGE_STEPS`).
``auto``
    For an automatic start (`ifslib.initialize("auto", target)`, `ifslib.discovery.auto`): a start
    is built for each candidate number of maps, each is fitted at the coarsest size of the pyramid
    for the same number of steps (`AUTO_PROBE_STEPS`), and the one with the lowest loss goes on
    through the pyramid's stages as in ``pyramid``; a shape then gets a stage at full size
    with the pixel loss (`POLISH_LOSS`), which fills the slivers between copies. With
    ``end_on_attractor`` (the default) that stage is the attractor stage (`attractor_stage`, with the
    pixel loss for a shape): it fills the slivers of the attractor itself.
    ``history["auto"]`` lists the candidates (maps, loss, steps, seconds) and the one chosen, and
    the fitted IFS's ``meta["pattern"]`` says so. A fractal's start (``kind="fractal"``: its maps
    and their number were chosen by `ifslib.discovery.fractal.search`) goes straight to the attractor
    stage, of at most `FRACTAL_STAGE_STEPS` steps with the single-scale pixel loss (`FRACTAL_LOSS`: the
    distance loss trades the attractor's thin detail for its outline, and the pooled copies of the
    multiscale pixel loss blur it); ``history["auto"]["candidates"]`` is then the
    search's table (per number of maps: cover, collage and attractor Chamfer distances, score).
``plain``
    One run: the paper's procedure (every step spent unless ``tol`` is given).
``coarse_to_fine``
    Depth 1, then 2, ... up to the full depth, the steps split evenly (cost: ``steps``).
``multistart``
    ``starts`` short probes (the given start, jittered copies of it, and for curves jittered
    best-fit-line starts), each ``probe`` steps; the ``keep`` best continue to ``steps``. Probes
    whose curve crosses itself rank after those that do not (the paper's local minima coincide with
    self-crossings). Cost: about ``2.9 * steps`` with the defaults.
``restart``
    Runs in windows; when a window ends without the figure within ``success`` pixels of the target
    and the loss has stopped improving, the next window starts from a jittered copy of the best
    points. Stops early on success. Cost: at most ``budget * steps``.
``anneal``
    The rendering width (pixel losses) or the pooling levels (distance losses) go from coarse to
    fine in four stages (cost: ``steps``).
``uncross``
    One run with a barrier on self-crossings added to the loss (curves only): ``crossing_weight``
    (default `UNCROSS_WEIGHT`) times the summed depth of the curve's crossings
    (`ifslib.crossings.crossing_penalty`), the paper's suggestion (cost: ``steps``).
"""
from __future__ import annotations

import copy
import math
import time

import numpy as np
import torch

from ..errors import IFSError, LeafBudgetError
from ..geometry.attractor import ATTRACTOR, is_attractor
from ..geometry.crossings import check_curve
from ..raster.distance import attractor_leaves_for
from ..geometry.ifs import IFS
from ..progress import note
from ..discovery.auto import candidates
from ..discovery.initialization import initialize, is_curve
from ..scoring.metrics import evaluate, self_crossings
from .run import FitResult, run
from ..targets.target import Target, pyramid_sizes, resize_target

STRATEGIES = ("pyramid", "auto", "plain", "coarse_to_fine", "multistart", "restart", "anneal", "uncross")

#: What `ifslib.fit` does when given no strategy.
DEFAULT_STRATEGY = "pyramid"

#: The crossing barrier's weight in ``uncross`` when the fit sets none.
UNCROSS_WEIGHT = 0.1

#: The pyramid's coarsest size in pixels: below it a Koch curve of depth 3 blurs into its own gaps.
COARSEST = 64

#: Each pyramid stage is this many times the size of the one before (4: 64² then 256²; a middle
#: 128² stage costs more time than it saves at 256², docs/results/fits-in-seconds.md).
PYRAMID_FACTOR = 4

#: At most this many steps in one pyramid stage (or ``steps``, when smaller): enough for the stages of starts
#: that recover, while a start that crawls on for a thousand steps ends stalled and is better replaced.
PYRAMID_STAGE_STEPS = 500

#: Steps each candidate of the ``auto`` strategy gets at the coarsest size before they are compared.
AUTO_PROBE_STEPS = 150

#: The ``auto`` strategy's last stage for a shape: the pixel loss counts every uncovered pixel, where
#: the distance loss hardly sees the slivers between copies (apple at 256²: IoU 0.89 -> 0.97).
POLISH_LOSS = "multiscale_pixel"

#: Early stop of each pyramid stage (see `ifslib.fitting.run.converged`) when the fit sets none.
PYRAMID_TOL, PYRAMID_PATIENCE = 1e-3, 30

#: A fractal's start (maps found by `ifslib.discovery.fractal.search`) gets one attractor stage of at
#: most this many steps: the search has placed its maps within a fraction of a pixel.
FRACTAL_STAGE_STEPS = 100
#: ... with this loss: the single-scale pixel loss scores what the fit is judged by (the attractor's IoU) better
#: than the multiscale pixel or a soft IoU loss, and quicker (docs/results/fractals.md).
FRACTAL_LOSS = "pixel"

#: ``pyramid`` and ``auto`` end with a stage that fits the attractor itself at the target's size (what
#: the inverse problem asks for: a drawing at depth K can match the target while its attractor does
#: not), of at most this many steps ...
ATTRACTOR_STAGE_STEPS = 300
#: ... with the certified cut (`ifslib.distance_field` with ``depth="attractor"``) when it has at most this
#: many leaves, else with sampled leaves of it (``method="sampled"``: overlapping copies of a shape).
FIT_MAX_LEAVES = 300_000


def attractor_method(ifs: IFS, size: int) -> str:
    """``"fast"`` when the certified cut of ``ifs``'s attractor at ``size`` has at most `FIT_MAX_LEAVES` leaves, else ``"sampled"``."""
    try:
        attractor_leaves_for(ifs, size, max_leaves=FIT_MAX_LEAVES)
    except LeafBudgetError:
        return "sampled"
    return "fast"


def attractor_stage(ifs: IFS, target: Target, steps: int, seed: int, lr: float, kwargs: dict, label: str,
                    loss: str | None = None) -> tuple[FitResult, dict]:
    """Fit the attractor of ``ifs`` at the target's size (the last stage of ``pyramid`` and ``auto``).

    Returns the run's result and its stage record (``size``, ``depth="attractor"``, ``method``,
    ``loss``, ``steps``, ``stopped``, ``best_loss``).
    """
    method = attractor_method(ifs, target.size)
    stage = {**kwargs, "depth": ATTRACTOR, "method": method}
    if loss is not None:
        stage["loss"] = loss
    record = {}

    def stage_run(note: str = "") -> FitResult:
        return run(ifs, target, steps=min(steps, ATTRACTOR_STAGE_STEPS), seed=seed, lr=lr,
                   desc=f"{label} · {target.size}² · attractor{note}", **stage)

    try:
        result = stage_run()
    except LeafBudgetError as exc:
        if method != "fast":
            raise
        # the maps grew on the way until the certified cut outgrew the leaf budget: the stage again, from its start,
        # with sampled leaves of the cut (whose number does not grow with the maps)
        method = stage["method"] = "sampled"
        record["fallback"] = f"the certified cut outgrew the leaf budget during the stage ({exc}); run again with sampled leaves"
        result = stage_run(" (sampled)")
    used = stage.get("loss", "multiscale_pixel")
    return result, {"size": target.size, "depth": ATTRACTOR, "method": method, "loss": used if isinstance(used, str)
                    else "custom", "steps": result.history["cost"], "stopped": result.history["stopped"],
                    "best_loss": result.best_loss, **record}


def check_strategy(strategy: str) -> str:
    """Return ``strategy`` if it is known, else raise `IFSError` naming the known ones."""
    if strategy not in STRATEGIES:
        raise IFSError(f"unknown strategy {strategy!r}; known strategies: {', '.join(STRATEGIES)}")
    return strategy


def _jittered(ifs: IFS, jitter: float, rng: np.random.Generator) -> IFS:
    pts = ifs.points.detach().double().numpy()
    return ifs.clone(torch.as_tensor(pts + rng.uniform(-jitter, jitter, pts.shape), dtype=ifs.points.dtype))


def _split(steps: int, parts: int) -> list[int]:
    """``steps`` split into ``parts`` stages as evenly as possible (the first ones one longer)."""
    return [steps // parts + (i < steps % parts) for i in range(parts)]


def _combine(results: list[FitResult], total_cost: int) -> FitResult:
    """The result with the lowest best loss, its history extended with the strategy's cost."""
    best = min(results, key=lambda r: r.best_loss)
    best.history["cost"] = total_cost
    return best


def _crosses(ifs: IFS) -> bool:
    if any(p.kind != "segment" for p in ifs.primitives):
        return False
    try:
        return self_crossings(ifs) > 0
    except IFSError:
        return True


def starts(ifs: IFS, target: Target, n: int, jitter: float, rng: np.random.Generator) -> list[IFS]:
    """``n`` starting points: ``ifs`` itself, then jittered copies of it and, for curves, every other
    one a best-fit-line start (`ifslib.initialize`): the first exactly on the line, the paper's
    advice and the start that recovers most often (docs/results/strategies.md), the later ones jittered."""
    out = [ifs]
    for k in range(1, n):
        if is_curve(ifs) and k % 2 == 1:
            line = initialize(ifs, target, jitter=0.0 if k == 1 else jitter, seed=int(rng.integers(2**31)))
            if k == 1 and torch.allclose(line.points, ifs.points):  # the given start is the line itself
                line = initialize(ifs, target, jitter=jitter, seed=int(rng.integers(2**31)))
            out.append(line)
        else:
            out.append(_jittered(ifs, jitter, rng))
    return out


def _pyramid_settings(kwargs: dict) -> float:
    """Turn early stopping on in ``kwargs`` (the pyramid's own tol and patience unless given) and pop the lr."""
    if kwargs.get("tol") is None:
        kwargs["tol"] = PYRAMID_TOL
    kwargs.setdefault("patience", PYRAMID_PATIENCE)
    return kwargs.pop("lr", 0.003)


def _climb(start: IFS, levels: dict, sizes: list[int], target_size: int, steps: int, seed: int, lr: float,
           kwargs: dict, label: str) -> tuple[FitResult, list[dict]]:
    """Fit ``start`` at each size of ``sizes`` in turn, each stage from the last one's best points."""
    stages, current, result = [], start, None
    for size in sizes:
        result = run(current, levels[size], steps=min(steps, PYRAMID_STAGE_STEPS), seed=seed,
                     lr=lr * target_size / size, desc=f"{label} · {size}²", **kwargs)
        stages.append({"size": size, "steps": result.history["cost"], "stopped": result.history["stopped"],
                       "best_loss": result.best_loss})
        current = result.best
    return result, stages


def _pyramid(ifs: IFS, target: Target, steps: int, seed: int, kwargs: dict, n_starts: int, jitter: float,
             success: float, coarsest: int, rng: np.random.Generator, end_on_attractor: bool) -> FitResult:
    """The ``pyramid`` strategy (see the module's docstring)."""
    lr = _pyramid_settings(kwargs)
    progress = kwargs.get("progress", True)
    sizes = pyramid_sizes(target.size, coarsest, PYRAMID_FACTOR)
    levels = {size: resize_target(target, size) for size in sizes}
    tried: list[tuple[FitResult, float]] = []
    stages, cost = [], 0
    final = end_on_attractor and not is_attractor(kwargs.get("depth"))
    for k, start in enumerate(starts(ifs, target, n_starts, jitter, rng)):
        label = f"start {k + 1}/{n_starts}"
        result, climbed = _climb(start, levels, sizes, target.size, steps, seed, lr, kwargs, label)
        if final:
            result, stage = attractor_stage(result.best, target, steps, seed, lr, kwargs, label)
            climbed.append(stage)
        cost += sum(st["steps"] for st in climbed)
        stages += [{"start": k, **st} for st in climbed]
        # judged on the full-size target, after the last stage only: a start far off at 64² can still
        # recover at full size; what is judged is the attractor when the fit ends on it
        chamfer = evaluate(result.best, target, depth=ATTRACTOR if final else None, attractor=False)["chamfer"]
        stages[-1]["chamfer"] = chamfer
        tried.append((result, chamfer))
        if chamfer <= success:
            break
        if progress:
            note(f"start {k + 1}/{n_starts}: Chamfer {chamfer:.2f} px > {success:g} px, trying the next start")
    best, chamfer = min(tried, key=lambda rc: rc[1])  # Chamfer at the full size: comparable across stages
    best.history.update(cost=cost, stages=stages, starts_tried=len(tried), chamfer=chamfer,
                        recovered=chamfer <= success, judged=ATTRACTOR if final else "depth")
    return best


def _auto(ifs: IFS, target: Target, steps: int, seed: int, kwargs: dict, coarsest: int,
          end_on_attractor: bool) -> FitResult:
    """The ``auto`` strategy (see the module's docstring)."""
    pattern = ifs.meta.get("pattern")
    if not (isinstance(pattern, dict) and pattern.get("name") == "auto"):
        raise IFSError("strategy 'auto' fits an automatic start: use ifslib.initialize('auto', target)")
    lr = _pyramid_settings(kwargs)
    if kwargs.pop("depth", None) not in (None, ifs.depth):
        raise IFSError("an automatic start's candidates have depths of their own: fix the depth with "
                       "ifslib.initialize('auto', target, depth=...)")
    sizes = pyramid_sizes(target.size, coarsest, PYRAMID_FACTOR)
    levels = {size: resize_target(target, size) for size in sizes}
    # the candidates the start was chosen among (`ifslib.discovery.auto.choices`); the start stands in for its own
    own = (pattern["maps"], ifs.depth)
    choices = [tuple(c) for c in pattern.get("choices", [own])]
    options = [ifs if c == own else candidates(target, [c], pattern.get("primitive", "box"), seed,
                                               kind=pattern.get("kind"))[0]
               for c in choices + [own] * (own not in choices)]
    if pattern.get("kind") == "fractal":
        return _auto_fractal(ifs, target, steps, seed, lr, kwargs, end_on_attractor)
    coarse, probe = sizes[0], min(steps, AUTO_PROBE_STEPS)
    tried = []
    for o in options:
        k = o.meta["pattern"]["maps"]
        t0 = time.perf_counter()
        result = run(o, levels[coarse], steps=probe, seed=seed, lr=lr * target.size / coarse,
                     desc=f"{k} maps, depth {o.depth} · {coarse}²", **kwargs)
        tried.append((result, {"maps": k, "depth": o.depth, "loss": result.best_loss, "steps": result.history["cost"],
                               "seconds": time.perf_counter() - t0}))
    # the lowest loss after the same number of steps; fewer maps win a tie
    winner, chosen = min(tried, key=lambda rc: (rc[1]["loss"], rc[1]["maps"]))
    kwargs["depth"] = chosen["depth"]
    result, stages = _climb(winner.best, levels, sizes, target.size, steps, seed, lr, kwargs,
                            f"{chosen['maps']} maps")
    if winner.best.meta["pattern"]["kind"] == "shape" and kwargs.get("loss") != POLISH_LOSS and not end_on_attractor:
        # The distance loss brings the copies over the figure from afar, but it hardly sees the
        # one-pixel slivers left between them; the pixel loss counts each uncovered pixel fully.
        polish = {**kwargs, "loss": POLISH_LOSS}
        result = run(result.best, target, steps=min(steps, PYRAMID_STAGE_STEPS), seed=seed, lr=lr,
                     desc=f"{chosen['maps']} maps · {target.size}² · {POLISH_LOSS}", **polish)
        stages.append({"size": target.size, "loss": POLISH_LOSS, "steps": result.history["cost"],
                       "stopped": result.history["stopped"], "best_loss": result.best_loss})
    if end_on_attractor:
        result, stage = attractor_stage(result.best, target, steps, seed, lr, kwargs, f"{chosen['maps']} maps",
                                        loss=POLISH_LOSS if winner.best.meta["pattern"]["kind"] == "shape" else None)
        stages.append(stage)
    cost = sum(c["steps"] for _, c in tried) + sum(s["steps"] for s in stages)
    choice = {**winner.best.meta["pattern"], "candidates": [c for _, c in tried], "chosen": chosen["maps"]}
    choice.pop("choices", None)
    result.history.update(cost=cost, stages=[{"maps": chosen["maps"], **st} for st in stages], auto=choice)
    for ifs_ in (result.best, result.final):
        ifs_.meta["pattern"] = {k: v for k, v in choice.items() if k != "candidates"}
    return result


def _auto_fractal(ifs: IFS, target: Target, steps: int, seed: int, lr: float, kwargs: dict,
                  end_on_attractor: bool) -> FitResult:
    """``auto`` for a fractal's start: its maps were found by the search (`ifslib.discovery.fractal`), so
    only the attractor stage is left (at most `FRACTAL_STAGE_STEPS` steps), or, without
    ``end_on_attractor``, a run of the drawing at its depth."""
    pattern = ifs.meta["pattern"]
    label = f"{pattern['maps']} maps"
    if end_on_attractor:
        result, stage = attractor_stage(ifs, target, min(steps, FRACTAL_STAGE_STEPS), seed, lr, kwargs, label,
                                        loss=FRACTAL_LOSS)
    else:
        kwargs = {**kwargs, "depth": ifs.depth}
        result = run(ifs, target, steps=min(steps, FRACTAL_STAGE_STEPS), seed=seed, lr=lr,
                     desc=f"{label} · {target.size}²", **kwargs)
        stage = {"size": target.size, "steps": result.history["cost"], "stopped": result.history["stopped"],
                 "best_loss": result.best_loss}
    choice = {**pattern, "candidates": pattern.get("search", []), "chosen": pattern["maps"]}
    choice.pop("search", None)
    result.history.update(cost=stage["steps"], stages=[{"maps": pattern["maps"], **stage}], auto=choice)
    for ifs_ in (result.best, result.final):
        ifs_.meta["pattern"] = {k: v for k, v in choice.items() if k != "candidates"}
    return result


def run_strategy(strategy: str, ifs: IFS, target: Target, steps: int, seed: int, kwargs: dict, *,
                 n_starts: int = 8, keep: int = 2, probe: float = 0.15, jitter: float = 0.05,
                 success: float = 1.0, budget: float = 3.0, coarsest: int = COARSEST,
                 end_on_attractor: bool = True) -> FitResult:
    """Run ``strategy`` with `ifslib.fitting.run.run` and its keyword arguments ``kwargs``.

    Parameters
    ----------
    strategy : str
        One of `STRATEGIES`.
    ifs, target, steps, seed
        As in `ifslib.fit`.
    kwargs : dict
        Further keyword arguments of `run` (``lr``, ``loss``, ``depth``, ``progress``, ...).
    n_starts, keep, probe, jitter, success, budget, coarsest
        The strategies' settings (see the module's docstring): ``success`` is the Chamfer
        distance in pixels at which ``pyramid`` and ``restart`` stop trying.
    end_on_attractor : bool
        ``pyramid`` and ``auto`` end each start with `attractor_stage` (and ``pyramid`` judges the
        attractor); False keeps them on the drawing at depth K.

    Returns
    -------
    FitResult
        The best run's result, with ``history["cost"]`` the Adam steps spent in all runs and
        ``history["strategy"]`` the strategy's name.
    """
    check_strategy(strategy)
    kwargs = dict(kwargs)
    given_depth = kwargs.get("depth")
    depth = kwargs.pop("depth", None) or ifs.depth
    rng = np.random.default_rng(seed)

    def one(start: IFS, n: int, **extra) -> FitResult:
        return run(start, target, steps=n, seed=seed, depth=extra.pop("depth", depth), **{**kwargs, **extra})

    if strategy == "auto":
        kwargs["depth"] = given_depth
        result = _auto(ifs, target, steps, seed, kwargs, coarsest, end_on_attractor)
    elif strategy == "pyramid":
        kwargs["depth"] = depth
        result = _pyramid(ifs, target, steps, seed, kwargs, n_starts, jitter, success, coarsest, rng, end_on_attractor)
    elif strategy == "plain":
        result = _combine([one(ifs, steps)], steps)
    elif strategy == "uncross":
        check_curve(ifs, "strategy 'uncross'")
        weight = kwargs.pop("crossing_weight", 0.0) or UNCROSS_WEIGHT
        result = _combine([one(ifs, steps, crossing_weight=weight)], steps)
    elif strategy == "coarse_to_fine":
        stages = list(range(1, depth + 1))
        current, results = ifs, []
        for d, n in zip(stages, _split(steps, len(stages))):
            results.append(one(current, n, depth=d))
            current = results[-1].best
        result = results[-1]
        result.history["cost"] = sum(r.history["cost"] for r in results)
    elif strategy == "multistart":
        n_probe = max(1, int(round(probe * steps)))
        probes = [one(c, n_probe, desc=f"probe {k + 1}/{n_starts} · {target.size}²")
                  for k, c in enumerate(starts(ifs, target, n_starts, jitter, rng))]
        order = sorted(range(len(probes)), key=lambda i: (_crosses(probes[i].best), probes[i].best_loss))
        finals = [one(probes[i].best, steps - n_probe, desc=f"continue {j + 1}/{keep} · {target.size}²") for j, i in enumerate(order[:keep])]
        result = _combine(finals, sum(r.history["cost"] for r in probes + finals))
    elif strategy == "restart":
        window = max(1, steps // 3)
        limit = int(budget * steps)
        spent, current, results = 0, ifs, []
        while spent < limit:
            n = min(window, limit - spent)
            results.append(one(current, n))
            spent += results[-1].history["cost"]
            best = min(results, key=lambda r: r.best_loss).best
            if evaluate(best, target, attractor=False)["chamfer"] <= success:
                break
            last = results[-1].history["loss"]
            improving = len(last) > 10 and min(last[-len(last) // 4:]) < 0.99 * min(last[:len(last) // 2])
            current = results[-1].best if improving else _jittered(best, jitter, rng)
        result = _combine(results, spent)
    else:  # anneal
        loss = kwargs.get("loss", "multiscale_pixel")
        current, results = ifs, []
        for stage, n in enumerate(_split(steps, 4)):
            if isinstance(loss, str) and loss.endswith("pixel"):
                extra = {"sigma": 2.0 ** (3 - stage) / target.size}
            else:
                extra = {"levels": kwargs.get("levels", 5) + 3 - stage}
            results.append(one(current, n, **extra))
            current = results[-1].best
        result = results[-1]
        result.history["cost"] = sum(r.history["cost"] for r in results)
    result.history["strategy"] = strategy
    for ifs_ in (result.best, result.final):  # what a saved fit records of how it was found
        ifs_.meta["history"] = copy.deepcopy(result.history)
    if not math.isfinite(result.best_loss):
        raise IFSError(f"strategy {strategy!r} found no finite loss")
    return result
