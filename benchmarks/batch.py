"""Batched fitting: many seeded starts of one pattern fitted in one computation, for `benchmarks/fit_many.py`
(its throughput against sequential `ifslib.fit` calls). A benchmark's helper, not the package's: on a CPU it
gains little (docs/results/fit-many.md), and the library's strategies run their starts one after another.

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

import math
import time
import warnings
from typing import Callable, Sequence

import numpy as np
import torch
from tqdm.auto import tqdm

from ifslib.core.geometry.leaves import Leaves, compose_words, word_geometry
from ifslib.core.geometry.primitives import PARAM_WIDTH, primitive_params
from ifslib.core.raster.distance import check_size, resolve_device
from ifslib.core.raster.leaf_distance import sdf_pairs
from ifslib.core.raster.nearest import nearest_leaf, pixel_centres
from ifslib.errors import IFSError, check_int
from ifslib.names import DEFAULT_STEPS
from ifslib.threads import refresh as refresh_threads
from ifslib.core.fitting.options import RunOptions, with_settings
from ifslib.core.fitting.result import FitResult, History
from ifslib.core.geometry.ifs import IFS, check_depth
from ifslib.core.scoring.losses import loss as loss_fn
from ifslib.core.geometry.rules import MIN_LENGTH, MIN_SINGULAR, rule_lengths, rule_maps, singular_values
from ifslib.core.targets.target import Target

#: Adam's constants, those of `torch.optim.Adam`'s defaults (which the descent, `ifslib.core.fitting.descent`, uses).
BETAS = (0.9, 0.999)
EPS = 1e-8


def _starts(ifs: IFS | Sequence[IFS] | Callable[[int], IFS], seeds: list[int], jitter: float) -> list[IFS]:
    """One starting IFS per seed, all of the same pattern."""
    if callable(ifs) and not isinstance(ifs, IFS):
        starts = [ifs(seed) for seed in seeds]
    elif isinstance(ifs, IFS):
        starts = [ifs.jittered(jitter, np.random.default_rng(seed)) for seed in seeds]
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


def expand_batch(ifs: IFS, points: torch.Tensor, depth: int | None = None, *, gradient: str = "exact") -> Leaves:
    """Expand a batch of point sets of one pattern to their leaves, in one computation.

    Parameters
    ----------
    ifs : IFS
        The pattern: rules and primitives (its own points are not used).
    points : torch.Tensor
        ``(B, n, 2)`` point sets, on the device and in the dtype to build with. They are not
        checked here: the caller makes sure every item's rules are non-degenerate and contractive
        (`ifslib.rules.rule_lengths`, `ifslib.rules.map_scales`).
    depth : int, optional
        ``K``; ``ifs.depth`` when None.
    gradient : {"exact", "paper"}

    Returns
    -------
    Leaves
        ``B * m**K`` words with ``words_per_item = m**K``; item ``b``'s leaves are those of
        ``expand(ifs.clone(points[b]))``.
    """
    depth = ifs.depth if depth is None else check_depth(depth)
    if points.ndim != 3 or points.shape[1:] != ifs.points.shape:
        raise IFSError(f"points must have shape (B, {ifs.n_points}, 2), got {tuple(points.shape)}")
    words = compose_words(rule_maps(points, ifs.rules, gradient), depth)  # (B, W, 3, 3)
    inverse, scale, forward = word_geometry(words, ifs.is_similarity)
    n_items, per_item = words.shape[:2]
    return Leaves(inverse.reshape(-1, 2, 3), scale.reshape(-1), primitive_params(points, ifs.primitives).reshape(-1, PARAM_WIDTH),
                  tuple(p.kind for p in ifs.primitives), per_item, None if forward is None else forward.reshape(-1, 6))


def distance_fields(ifs: IFS, points: torch.Tensor, size: int, depth: int | None = None, *,
                    gradient: str = "exact") -> torch.Tensor:
    """`distance_field` of ``(B, n, 2)`` point sets of one pattern in one computation (each item's rules contractive)."""
    check_size(size)
    leaves = expand_batch(ifs, points, depth, gradient=gradient)
    x, y = pixel_centres(size, points.device, points.dtype)
    n_items = points.shape[0]
    # smaller chunks than one field's: a batch's pair lists outgrow the cache
    winner = nearest_leaf(leaves, size, max_pairs=1 << 18).leaf
    return sdf_pairs(leaves, x.repeat(n_items), y.repeat(n_items), winner).view(n_items, size, size)


def fit_many(ifs: IFS | Sequence[IFS] | Callable[[int], IFS], target: Target, *, seeds: Sequence[int] = range(8),
             steps: int = DEFAULT_STEPS, options: RunOptions | None = None, jitter: float = 0.0, progress: bool = True,
             **settings) -> list[FitResult]:
    """Fit many seeded starts of one pattern at once, with a leading batch dimension.

    Parameters
    ----------
    ifs : IFS, sequence of IFS, or callable
        The starts: a function ``seed -> IFS`` (such as `ifslib.patterns.koch_paper`), one IFS per
        seed, or one IFS that every seed starts from (jittered by ``jitter``).
    target : Target
    seeds : sequence of int
        One fit per seed; the seed picks the start (and seeds torch, as in `ifslib.fit`).
    steps : int
        As in `ifslib.fit`.
    options : RunOptions, optional
        As in `ifslib.fit`, of which a batch uses ``lr``, ``loss``, ``depth`` (an integer),
        ``sigma``, ``levels``, ``gradient``, ``max_rollbacks`` and ``device`` (``"auto"`` uses CUDA
        when present); the others must keep their defaults.
    **settings
        Those fields by name, over ``options``.
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
    options = with_settings(options, settings)
    _check_batchable(options)
    refresh_threads()  # in auto mode: the cores free now (see ifslib.threads)
    lr, loss, sigma, levels, gradient = options.step_lr, options.loss, options.sigma, options.levels, options.gradient
    max_rollbacks = options.max_rollbacks
    starts = _starts(ifs, seeds, jitter)
    pattern = starts[0]
    depth = pattern.depth if options.depth is None else check_depth(options.depth)
    dev = resolve_device(options.device)
    n = len(seeds)
    torch.manual_seed(seeds[0])

    state = _Batch(torch.stack([s.points.detach() for s in starts]).to(dev), lr)
    histories = [History() for _ in seeds]
    bar = tqdm(total=steps, disable=not progress, desc=f"fit_many ({n})", unit="step")
    for step in range(steps):
        if not bool(state.active.any()):
            break
        t0 = time.perf_counter()
        with torch.no_grad():
            valid = _valid(pattern, state.points, depth, gradient)
        # items whose points are invalid are evaluated at their last good points, then rolled back
        work = torch.where(valid[:, None, None], state.points, state.previous[0]).requires_grad_(True)
        field = distance_fields(pattern, work, target.size, depth, gradient=gradient)
        values = loss_fn(field, target, loss, sigma=sigma, levels=levels)
        finite = torch.isfinite(values)
        torch.where(finite, values, 0).sum().backward()
        ok = state.active & valid & finite & torch.isfinite(work.grad).flatten(1).all(dim=1)
        fail = state.active & ~ok
        with torch.no_grad():
            current = state.step(step, values.detach().double(), work.grad, ok, fail, list(pattern.fixed))
        _record(histories, step, current, ok, fail, valid, finite, state.rates, (time.perf_counter() - t0) / n)
        stopped = fail & (state.consecutive >= max_rollbacks)
        for i in stopped.nonzero().flatten().tolist():
            warnings.warn(f"fit_many: seed {seeds[i]} stopped at step {step}: {max_rollbacks} consecutive "
                          "rolled-back steps")
        state.active &= ~stopped
        if progress and step % 10 == 0 and bool(ok.any()):
            bar.set_postfix(median_loss=f"{current[ok].median().item():.3g}")
        bar.update(1)
    bar.close()
    results = []
    for i, start in enumerate(starts):
        history = histories[i]
        history.cost = len(history.step) + len(history.rollbacks)
        best, final = start.clone(state.best_points[i].cpu()), start.clone(state.points[i].cpu())
        results.append(FitResult(best, final, history, float(state.best_loss[i]), int(state.best_step[i])).record())
    return results


class _Batch:
    """The points, Adam's state and the best points of ``B`` fits, each item on its own."""

    def __init__(self, points: torch.Tensor, lr: float):
        n, dev = len(points), points.device
        self.points = points
        self.exp_avg, self.exp_avg_sq = torch.zeros_like(points), torch.zeros_like(points)
        self.count = torch.zeros(n, dtype=torch.float64, device=dev)          # Adam's step count per item
        self.rates = torch.full((n,), float(lr), dtype=torch.float64, device=dev)
        self.previous = [points.clone(), self.exp_avg.clone(), self.exp_avg_sq.clone(), self.count.clone()]
        self.best_loss = torch.full((n,), math.inf, dtype=torch.float64, device=dev)
        self.best_step = torch.full((n,), -1, dtype=torch.long, device=dev)
        self.best_points = points.clone()
        self.active = torch.ones(n, dtype=torch.bool, device=dev)
        self.consecutive = torch.zeros(n, dtype=torch.long, device=dev)

    def step(self, step: int, current: torch.Tensor, grad: torch.Tensor, ok: torch.Tensor, fail: torch.Tensor,
             fixed: list[int]) -> torch.Tensor:
        """Roll back the failed items, keep the best points, take Adam's step on the others; returns ``current``."""
        if bool(fail.any()):
            self.rollback(fail)
        self.consecutive = torch.where(ok, 0, self.consecutive)
        better = ok & (current < self.best_loss)
        self.best_loss = torch.where(better, current, self.best_loss)
        self.best_step = torch.where(better, step, self.best_step)
        self.best_points = torch.where(better[:, None, None], self.points, self.best_points)
        k = ok[:, None, None]
        self.previous = [torch.where(k, self.points, self.previous[0]), torch.where(k, self.exp_avg, self.previous[1]),
                         torch.where(k, self.exp_avg_sq, self.previous[2]), torch.where(ok, self.count, self.previous[3])]
        grad = torch.where(k, grad, 0)
        if fixed:
            grad[:, fixed] = 0
        self.adam(grad, ok)
        return current

    def rollback(self, fail: torch.Tensor) -> None:
        """The failed items back to the points before the step that led there, at half their learning rate."""
        f = fail[:, None, None]
        self.points = torch.where(f, self.previous[0], self.points)
        self.exp_avg = torch.where(f, self.previous[1], self.exp_avg)
        self.exp_avg_sq = torch.where(f, self.previous[2], self.exp_avg_sq)
        self.count = torch.where(fail, self.previous[3], self.count)
        self.rates = torch.where(fail, self.rates * 0.5, self.rates)
        self.consecutive = torch.where(fail, self.consecutive + 1, self.consecutive)

    def adam(self, grad: torch.Tensor, ok: torch.Tensor) -> None:
        """Adam, item by item, in the order of operations of torch.optim.Adam (single-tensor path).

        The library's one Adam besides the descent's (`ifslib.core.fitting.descent`, torch's Adam):
        `torch.optim.Adam` keeps one step count and one learning rate a tensor, and a batch's items each
        keep their own (a rolled-back item halves its rate and keeps its count), as each single run
        does with torch's.
        """
        beta1, beta2 = BETAS
        k = ok[:, None, None]
        new_count = self.count + 1
        new_avg = self.exp_avg.lerp(grad, 1 - beta1)
        new_avg_sq = self.exp_avg_sq.mul(beta2).addcmul(grad, grad, value=1 - beta2)
        step_size = (self.rates / (1 - beta1 ** new_count)).to(self.points.dtype)[:, None, None]
        root = ((1 - beta2 ** new_count) ** 0.5).to(self.points.dtype)[:, None, None]
        moved = self.points - step_size * new_avg / (new_avg_sq.sqrt() / root + EPS)
        self.points = torch.where(k, moved, self.points)
        self.exp_avg = torch.where(k, new_avg, self.exp_avg)
        self.exp_avg_sq = torch.where(k, new_avg_sq, self.exp_avg_sq)
        self.count = torch.where(ok, new_count, self.count)


def _record(histories: list[History], step: int, current, ok, fail, valid, finite, rates, seconds: float) -> None:
    """Each item's step in its history: its loss, or why it was rolled back."""
    values_list, ok_list, fail_list = current.tolist(), ok.tolist(), fail.tolist()
    for i, history in enumerate(histories):
        if ok_list[i]:
            history.step.append(step)
            history.loss.append(values_list[i])
            history.seconds.append(seconds)
        elif fail_list[i]:
            reason = ("a rule became degenerate or non-contractive" if not bool(valid[i]) else
                      f"loss is {values_list[i]}" if not bool(finite[i]) else "gradient is not finite")
            history.rollbacks.append({"step": step, "reason": reason, "lr": float(rates[i])})


def _check_batchable(options: RunOptions) -> None:
    """Refuse the settings a batch does not carry (a batch renders at a fixed depth with the fast method)."""
    unsupported = {name: getattr(options, name) for name in ("method", "keep_every", "crossing_weight", "tol", "patience")
                   if getattr(options, name) != getattr(RunOptions(), name)}
    if unsupported:
        raise IFSError(f"fit_many does not take {', '.join(unsupported)}: fit those starts one by one with ifslib.fit")


__all__ = ["distance_fields", "expand_batch", "fit_many"]
