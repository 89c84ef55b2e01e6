"""Strategies that escape local minima, built on the single-run `fit` loop.

A strategy spends Adam steps across several runs of `ifslib.fit` and returns the best result. Every
step of every run counts in ``history["cost"]``, so strategies compare per step spent:

``plain``
    One run: the paper's procedure.
``coarse_to_fine``
    Depth 1, then 2, ... up to the full depth, the steps split evenly (cost: ``steps``).
``multistart``
    ``starts`` short probes (the given start, jittered copies of it, and for curves jittered
    best-fit-line starts), each ``probe`` steps; the ``keep`` best continue to ``steps``. Probes
    whose curve crosses itself rank after those that do not (the paper's local minima coincide with
    self-crossings). Cost: about ``2.9 * steps`` with the defaults.
``restart``
    Runs in windows; when a window ends without the figure within ``success_chamfer`` pixels of the
    target and the loss has stopped improving, the next window starts from a jittered copy of the
    best points. Stops early on success. Cost: at most ``budget * steps``.
``anneal``
    The rendering width (pixel losses) or the pooling levels (distance losses) go from coarse to
    fine in four stages (cost: ``steps``).
``uncross``
    One run with a barrier on self-crossings added to the loss (curves only): ``crossing_weight``
    (default `UNCROSS_WEIGHT`) times the summed depth of the curve's crossings
    (`ifslib.crossings.crossing_penalty`), the paper's suggestion (cost: ``steps``).
"""
from __future__ import annotations

import math

import numpy as np
import torch

from ..geometry.crossings import check_curve
from ..errors import IFSError
from ..geometry.ifs import IFS
from .initialization import initialize, is_curve
from .metrics import evaluate, self_crossings
from .targets import Target

STRATEGIES = ("plain", "coarse_to_fine", "multistart", "restart", "anneal", "uncross")

#: What `ifslib.fit` does when given no strategy: the most reliable one in the convergence study.
DEFAULT_STRATEGY = "multistart"

#: The crossing barrier's weight in ``uncross`` when the fit sets none.
UNCROSS_WEIGHT = 0.1


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


def _combine(results: list, total_cost: int):
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


def run(strategy: str, fit, ifs: IFS, target: Target, steps: int, seed: int, kwargs: dict, *,
        starts: int = 8, keep: int = 2, probe: float = 0.15, jitter: float = 0.05,
        success_chamfer: float = 1.0, budget: float = 3.0):
    """Run ``strategy`` with ``fit`` (the single-run loop) and the fit keyword arguments ``kwargs``.

    Returns the best `FitResult`, with ``history["cost"]`` the Adam steps spent in all runs and
    ``history["strategy"]`` its name.
    """
    check_strategy(strategy)
    depth = kwargs.pop("depth", None) or ifs.depth
    rng = np.random.default_rng(seed)

    def one(start: IFS, n: int, **extra):
        return fit(start, target, steps=n, seed=seed, depth=extra.pop("depth", depth), strategy="plain",
                   **{**kwargs, **extra})

    if strategy == "plain":
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
        result.history["cost"] = steps
    elif strategy == "multistart":
        n_probe = max(1, int(round(probe * steps)))
        candidates = [ifs]
        for k in range(1, starts):
            if is_curve(ifs) and k % 2 == 1:
                candidates.append(initialize(ifs, target, jitter=jitter, seed=int(rng.integers(2**31))))
            else:
                candidates.append(_jittered(ifs, jitter, rng))
        probes = [one(c, n_probe) for c in candidates]
        order = sorted(range(len(probes)), key=lambda i: (_crosses(probes[i].best), probes[i].best_loss))
        finals = [one(probes[i].best, steps - n_probe) for i in order[:keep]]
        result = _combine(finals, n_probe * len(candidates) + (steps - n_probe) * len(finals))
    elif strategy == "restart":
        window = max(1, steps // 3)
        limit = int(budget * steps)
        spent, current, results = 0, ifs, []
        while spent < limit:
            n = min(window, limit - spent)
            results.append(one(current, n))
            spent += n
            best = min(results, key=lambda r: r.best_loss).best
            if evaluate(best, target)["chamfer"] <= success_chamfer:
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
        result.history["cost"] = steps
    result.history["strategy"] = strategy
    if not math.isfinite(result.best_loss):
        raise IFSError(f"strategy {strategy!r} found no finite loss")
    return result
