"""Batched fitting: many seeded starts of one pattern fitted in one computation.

`fit_many` stacks the control points of ``B`` starts into one ``(B, n, 2)`` tensor and carries that
leading batch dimension through maps, leaves, the nearest-leaf search, the distance and the loss.
The batch's loss is the sum of the items' losses, so each item's gradient is that of its own loss;
Adam is applied item by item (its own step count and learning rate), and a step that fails for one
item (a degenerate or non-contractive rule, a non-finite loss or gradient) is rolled back for that
item only, exactly as the single run `ifslib.fitting.run.run` does. So each item follows the path
that ``run(start, target, seed=seed)`` (``ifslib.fit(..., strategy="plain")``) follows, up to
floating-point rounding. It sits beside `run` at the bottom of the fitting layer.

On a CPU a step's cost is the (pixel, leaf) pairs, which batching does not reduce, so it gains
little there (docs/results/fit-many.md); the default strategy runs its starts one after another
(and usually needs only the first).
"""
from __future__ import annotations

import copy
import math
import time
import warnings
from typing import Callable, Sequence

import numpy as np
import torch
from tqdm.auto import tqdm

from ..raster.distance import distance_fields, resolve_device
from ..errors import IFSError, check_int
from ..threads import refresh as refresh_threads
from .run import FitResult
from ..geometry.ifs import IFS, check_depth
from ..scoring.losses import loss as loss_fn
from ..geometry.rules import MIN_LENGTH, MIN_SINGULAR, check_gradient_mode, rule_lengths, rule_maps, singular_values
from ..targets.target import Target

#: Adam's constants, those of `torch.optim.Adam`'s defaults (which `ifslib.fitting.run.run` uses).
BETAS = (0.9, 0.999)
EPS = 1e-8


def _starts(ifs: IFS | Sequence[IFS] | Callable[[int], IFS], seeds: list[int], jitter: float) -> list[IFS]:
    """One starting IFS per seed, all of the same pattern."""
    if callable(ifs) and not isinstance(ifs, IFS):
        starts = [ifs(seed) for seed in seeds]
    elif isinstance(ifs, IFS):
        starts = []
        for seed in seeds:
            pts = ifs.points.detach().double().numpy().copy()
            if jitter:
                free = [i for i in range(len(pts)) if i not in ifs.fixed]
                noise = np.random.default_rng(seed).uniform(-jitter, jitter, size=pts.shape)
                pts[free] += noise[free]
            starts.append(ifs.clone(torch.as_tensor(pts, dtype=ifs.points.dtype)))
    else:
        starts = list(ifs)
        if len(starts) != len(seeds):
            raise IFSError(f"got {len(starts)} starting IFSs for {len(seeds)} seeds: give one per seed")
    first = starts[0]
    for i, start in enumerate(starts):
        if not isinstance(start, IFS):
            raise IFSError(f"start {i} is a {type(start).__name__}, not an IFS")
        if (start.rules != first.rules or start.primitives != first.primitives or start.points.shape != first.points.shape
                or start.fixed != first.fixed or start.points.dtype != first.points.dtype):
            raise IFSError(f"start {i} is not the same pattern as start 0 (rules, primitives, points, fixed points "
                           "and dtype must agree): fit_many fits starts of one pattern")
    return starts


def _valid(pattern: IFS, points: torch.Tensor, depth: int, gradient: str) -> torch.Tensor:
    """``(B,)``: which point sets make finite, non-degenerate and (for depth > 0) contractive rules."""
    ok = torch.isfinite(points).all(dim=-1).all(dim=-1)
    ok &= (rule_lengths(points, pattern.rules) > MIN_LENGTH).all(dim=-1)
    if depth > 0:
        safe = torch.where(ok[:, None, None], points, pattern.points.detach().to(points))
        smallest, largest = singular_values(rule_maps(safe, pattern.rules, gradient))
        ok &= (largest < 1).all(dim=-1) & (smallest >= MIN_SINGULAR).all(dim=-1)  # as IFS.check_contractive
    return ok


def fit_many(ifs: IFS | Sequence[IFS] | Callable[[int], IFS], target: Target, seeds: Sequence[int] = range(8),
             steps: int = 1500, lr: float = 0.003, loss: str | Callable = "multiscale_pixel", depth: int | None = None,
             sigma: float | None = None, levels: int = 5, device: str = "auto", gradient: str = "exact",
             max_rollbacks: int = 20, jitter: float = 0.0, progress: bool = True) -> list[FitResult]:
    """Fit many seeded starts of one pattern at once, with a leading batch dimension.

    Parameters
    ----------
    ifs : IFS, sequence of IFS, or callable
        The starts: a function ``seed -> IFS`` (such as `ifslib.patterns.koch_paper`), one IFS per
        seed, or one IFS that every seed starts from (jittered by ``jitter``).
    target : Target
    seeds : sequence of int
        One fit per seed; the seed picks the start (and seeds torch, as in `ifslib.fit`).
    steps, lr, loss, depth, sigma, levels, gradient, max_rollbacks
        As in `ifslib.fit` (method ``"fast"``).
    device : {"auto", "cpu", "cuda"}
        Where the batch is computed; ``"auto"`` uses CUDA when present.
    jitter : float
        With one IFS: half-width of the uniform jitter ``U(-jitter, jitter)`` added to its free
        points, drawn from ``numpy.random.default_rng(seed)``.
    progress : bool
        Show a tqdm progress bar.

    Returns
    -------
    list of FitResult
        One per seed, in order: what ``ifslib.fit(..., strategy="plain")`` returns for that start (``history`` holds
        ``step``, ``loss``, ``seconds`` (the batched step's time divided by the batch size),
        ``rollbacks`` and ``cost``).

    Raises
    ------
    IFSError
        No seeds, starts of different patterns, or a bad argument.
    """
    seeds = [int(s) for s in seeds]
    if not seeds:
        raise IFSError("fit_many needs at least one seed")
    check_int(steps, "steps", 0)
    refresh_threads()  # in auto mode: the cores free now (see ifslib.threads)
    check_int(max_rollbacks, "max_rollbacks", 1)
    check_gradient_mode(gradient)
    if not (isinstance(lr, (int, float)) and lr > 0 and math.isfinite(lr)):
        raise IFSError(f"lr must be a finite number > 0, got {lr!r}")
    starts = _starts(ifs, seeds, jitter)
    pattern = starts[0]
    depth = pattern.depth if depth is None else check_depth(depth)
    dev = resolve_device(device)
    n = len(seeds)
    torch.manual_seed(seeds[0])

    points = torch.stack([s.points.detach() for s in starts]).to(dev)
    exp_avg, exp_avg_sq = torch.zeros_like(points), torch.zeros_like(points)
    count = torch.zeros(n, dtype=torch.float64, device=dev)          # Adam's step count per item
    rates = torch.full((n,), float(lr), dtype=torch.float64, device=dev)
    previous = [points.clone(), exp_avg.clone(), exp_avg_sq.clone(), count.clone()]
    best_loss = torch.full((n,), math.inf, dtype=torch.float64, device=dev)
    best_step = torch.full((n,), -1, dtype=torch.long, device=dev)
    best_points = points.clone()
    active = torch.ones(n, dtype=torch.bool, device=dev)
    consecutive = torch.zeros(n, dtype=torch.long, device=dev)
    histories = [{"step": [], "loss": [], "seconds": [], "rollbacks": []} for _ in seeds]
    fixed = list(pattern.fixed)
    beta1, beta2 = BETAS

    bar = tqdm(total=steps, disable=not progress, desc=f"fit_many ({n})", unit="step")
    for step in range(steps):
        if not bool(active.any()):
            break
        t0 = time.perf_counter()
        with torch.no_grad():
            valid = _valid(pattern, points, depth, gradient)
        # items whose points are invalid are evaluated at their last good points, then rolled back
        work = torch.where(valid[:, None, None], points, previous[0]).requires_grad_(True)
        field = distance_fields(pattern, work, target.size, depth, gradient=gradient)
        values = loss_fn(field, target, loss, sigma=sigma, levels=levels)
        finite = torch.isfinite(values)
        torch.where(finite, values, 0).sum().backward()
        grad = work.grad
        ok = active & valid & finite & torch.isfinite(grad).flatten(1).all(dim=1)
        fail = active & ~ok
        with torch.no_grad():
            if bool(fail.any()):
                # roll back to the points before the step that led here, and halve the learning rate
                f = fail[:, None, None]
                points = torch.where(f, previous[0], points)
                exp_avg = torch.where(f, previous[1], exp_avg)
                exp_avg_sq = torch.where(f, previous[2], exp_avg_sq)
                count = torch.where(fail, previous[3], count)
                rates = torch.where(fail, rates * 0.5, rates)
                consecutive = torch.where(fail, consecutive + 1, consecutive)
            consecutive = torch.where(ok, 0, consecutive)
            current = values.detach().double()
            better = ok & (current < best_loss)
            best_loss = torch.where(better, current, best_loss)
            best_step = torch.where(better, step, best_step)
            best_points = torch.where(better[:, None, None], points, best_points)
            k = ok[:, None, None]
            previous = [torch.where(k, points, previous[0]), torch.where(k, exp_avg, previous[1]),
                        torch.where(k, exp_avg_sq, previous[2]), torch.where(ok, count, previous[3])]
            grad = torch.where(k, grad, 0)
            if fixed:
                grad[:, fixed] = 0
            # Adam, item by item, in the order of operations of torch.optim.Adam (single-tensor path)
            new_count = count + 1
            new_avg = exp_avg.lerp(grad, 1 - beta1)
            new_avg_sq = exp_avg_sq.mul(beta2).addcmul(grad, grad, value=1 - beta2)
            step_size = (rates / (1 - beta1 ** new_count)).to(points.dtype)[:, None, None]
            root = ((1 - beta2 ** new_count) ** 0.5).to(points.dtype)[:, None, None]
            moved = points - step_size * new_avg / (new_avg_sq.sqrt() / root + EPS)
            points = torch.where(k, moved, points)
            exp_avg = torch.where(k, new_avg, exp_avg)
            exp_avg_sq = torch.where(k, new_avg_sq, exp_avg_sq)
            count = torch.where(ok, new_count, count)
        seconds = (time.perf_counter() - t0) / n
        values_list, ok_list, fail_list = current.tolist(), ok.tolist(), fail.tolist()
        for i in range(n):
            if ok_list[i]:
                histories[i]["step"].append(step)
                histories[i]["loss"].append(values_list[i])
                histories[i]["seconds"].append(seconds)
            elif fail_list[i]:
                reason = ("a rule became degenerate or non-contractive" if not bool(valid[i]) else
                          f"loss is {values_list[i]}" if not bool(finite[i]) else "gradient is not finite")
                histories[i]["rollbacks"].append({"step": step, "reason": reason, "lr": float(rates[i])})
        stopped = fail & (consecutive >= max_rollbacks)
        for i in stopped.nonzero().flatten().tolist():
            warnings.warn(f"fit_many: seed {seeds[i]} stopped at step {step}: {max_rollbacks} consecutive "
                          "rolled-back steps")
        active &= ~stopped
        if progress and step % 10 == 0 and bool(ok.any()):
            bar.set_postfix(median_loss=f"{current[ok].median().item():.3g}")
        bar.update(1)
    bar.close()

    results = []
    for i, start in enumerate(starts):
        history = histories[i]
        history["cost"] = len(history["step"]) + len(history["rollbacks"])
        best = start.clone(best_points[i].cpu())
        best.meta["history"] = copy.deepcopy(history)
        final = start.clone(points[i].cpu())
        final.meta["history"] = copy.deepcopy(history)
        results.append(FitResult(best, final, history, float(best_loss[i]), int(best_step[i])))
    return results


__all__ = ["fit_many"]
