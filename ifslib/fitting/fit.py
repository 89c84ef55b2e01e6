"""The optimization loop: Adam on the control points, with rollback, checkpoints and progress.

`fit` moves an IFS's control points so that its rendering matches a target: the inverse IFS
problem. Each step renders the distance field (exact nearest leaf, exact gradient), takes a loss
against the target, and lets Adam move the points. A step whose loss or gradient is not finite,
or whose points make a rule degenerate or non-contractive, is rolled back (the points and the
optimizer go back to before the step that led there, the learning rate is halved) and reported in
the history instead of poisoning the points.
"""
from __future__ import annotations

import copy
import math
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import torch
from tqdm.auto import tqdm

from ..geometry.crossings import check_curve, crossing_penalty
from ..raster.distance import distance_field
from ..errors import IFSError, check_int
from ..geometry.ifs import IFS, check_depth
from ..geometry.io import ifs_to_dict, load_ifs, save_ifs
from .losses import loss as loss_fn
from .targets import Target


@dataclass
class FitResult:
    """What `fit` returns.

    Attributes
    ----------
    best : IFS
        The points with the lowest loss seen.
    final : IFS
        The points after the last step.
    history : dict
        Per step: ``step``, ``loss`` (at the points before that step), ``seconds``; and
        ``rollbacks``, a list of ``{"step", "reason", "lr"}``.
    best_loss : float
    best_step : int
    """

    best: IFS
    final: IFS
    history: dict = field(default_factory=dict)
    best_loss: float = math.inf
    best_step: int = -1


def _adam_state(opt: torch.optim.Adam) -> dict:
    """A copy of Adam's state for the one parameter (tensors)."""
    state = opt.state[opt.param_groups[0]["params"][0]]
    if not state:
        return {}
    return {"step": float(state["step"]), "exp_avg": state["exp_avg"].clone(), "exp_avg_sq": state["exp_avg_sq"].clone()}


def _as_lists(state: dict) -> dict:
    return {k: v.tolist() if isinstance(v, torch.Tensor) else v for k, v in state.items()}


def _set_adam_state(opt: torch.optim.Adam, saved: dict, lr: float) -> None:
    param = opt.param_groups[0]["params"][0]
    opt.param_groups[0]["lr"] = lr
    opt.state.clear()
    if saved:
        opt.state[param] = {"step": torch.tensor(saved["step"]),
                            "exp_avg": torch.as_tensor(saved["exp_avg"], dtype=param.dtype).clone(),
                            "exp_avg_sq": torch.as_tensor(saved["exp_avg_sq"], dtype=param.dtype).clone()}


def fit(ifs: IFS, target: Target, steps: int = 1500, lr: float = 0.003, loss: str | Callable = "multiscale_pixel",
        depth: int | None = None, seed: int = 0, callback: Callable | None = None, checkpoint: str | Path | None = None,
        checkpoint_every: int = 100, resume: str | Path | None = None, progress: bool = True,
        sigma: float | None = None, levels: int = 5, method: str = "fast", device: str = "auto",
        gradient: str = "exact", max_rollbacks: int = 20, keep_every: int | None = None,
        strategy: str | None = None, crossing_weight: float = 0.0) -> FitResult:
    """Fit an IFS's control points to a target with Adam.

    Parameters
    ----------
    ifs : IFS
        The starting point (not modified).
    target : Target
        From `ifslib.load_target`; its size sets the render size.
    steps : int
        Total number of Adam steps (the paper used 1500).
    lr : float
        Learning rate (the paper used 0.003).
    loss : str or callable
        ``pixel``, ``multiscale_pixel``, ``distance``, ``multiscale_distance`` or ``f(distance, target)``.
    depth : int, optional
        Render depth (``ifs.depth`` when None).
    seed : int
        Seeds torch before the loop; a seeded run on CPU is reproducible.
    callback : callable, optional
        ``callback(step, loss, ifs)`` after every step.
    checkpoint : path, optional
        Write the IFS JSON, with the optimizer state and history, atomically every
        ``checkpoint_every`` steps and at the end.
    resume : path, optional
        A checkpoint to continue from: the result equals that of an uninterrupted run.
    progress : bool
        Show a tqdm progress bar.
    sigma, levels
        Passed to the loss.
    method, device, gradient
        Passed to `ifslib.distance_field` (``gradient="paper"`` reproduces the paper's cut gradient).
    max_rollbacks : int
        Stop after this many consecutive rolled-back steps.
    keep_every : int, optional
        Keep the control points every ``keep_every`` steps (and after the last step) in
        ``history["snapshots"]``, with the pattern in ``history["pattern"]``, for `ifslib.animate`.
        None (the default) keeps nothing and costs nothing.
    strategy : str, optional
        How the steps are spent. None (the default) is `ifslib.strategies.DEFAULT_STRATEGY`
        (``"multistart"``, the most reliable in our study: short probes from several starts, the
        best two continued, about 2.9x the steps of one run), except that a run with ``checkpoint``
        or ``resume`` is a single run. ``"plain"`` is one run, the paper's procedure; the others
        (``coarse_to_fine``, ``restart``, ``anneal``, ``uncross``) are in `ifslib.strategies`.
        ``history["cost"]`` counts every step of every run.
    crossing_weight : float
        For curves: add ``crossing_weight * ifslib.crossings.crossing_penalty(ifs)`` (the summed depth
        of the curve's self-crossings, in plane units) to the loss, the barrier the paper suggests.
        0 (the default) adds nothing.

    Returns
    -------
    FitResult
    """
    check_int(steps, "steps", 0)
    if not (isinstance(crossing_weight, (int, float)) and crossing_weight >= 0 and math.isfinite(crossing_weight)):
        raise IFSError(f"crossing_weight must be a finite number >= 0, got {crossing_weight!r}")
    if crossing_weight:
        check_curve(ifs, "crossing_weight")
    if strategy is None:
        from .strategies import DEFAULT_STRATEGY

        strategy = "plain" if checkpoint is not None or resume is not None else DEFAULT_STRATEGY
    if strategy != "plain":
        from .strategies import check_strategy, run

        check_strategy(strategy)
        if checkpoint is not None or resume is not None:
            raise IFSError("checkpoint and resume work with strategy='plain' only")
        return run(strategy, fit, ifs, target, steps, seed,
                   dict(lr=lr, loss=loss, depth=depth, callback=callback, progress=progress, sigma=sigma,
                        levels=levels, method=method, device=device, gradient=gradient,
                        max_rollbacks=max_rollbacks, keep_every=keep_every, crossing_weight=crossing_weight))
    if keep_every is not None:
        check_int(keep_every, "keep_every", 1)
    if not (isinstance(lr, (int, float)) and lr > 0 and math.isfinite(lr)):
        raise IFSError(f"lr must be a finite number > 0, got {lr!r}")
    depth = ifs.depth if depth is None else check_depth(depth)
    torch.manual_seed(seed)
    work = ifs.clone()
    fixed = list(work.fixed)
    opt = torch.optim.Adam([work.points], lr=lr)
    history: dict = {"step": [], "loss": [], "seconds": [], "rollbacks": []}
    start, best_loss, best_step = 0, math.inf, -1
    best_points = work.points.detach().clone()
    if resume is not None:
        saved = load_ifs(resume)
        state = saved.meta.get("fit")
        if not state:
            raise IFSError(f"{resume} is not a fit checkpoint (no 'fit' entry in its meta)")
        with torch.no_grad():
            work.points.copy_(saved.points.to(work.points.dtype))
        lr = state["lr"]
        _set_adam_state(opt, state["adam"], lr)
        start, best_loss, best_step = state["next_step"], state["best_loss"], state["best_step"]
        best_points = torch.tensor(state["best_points"], dtype=work.points.dtype)
        history = state["history"]
    if keep_every is not None and "snapshots" not in history:
        history["pattern"] = ifs_to_dict(ifs)
        history["snapshots"] = {"step": [], "points": []}
    previous = (work.points.detach().clone(), _adam_state(opt))
    consecutive = 0

    def save(step_done: int) -> None:
        snap = work.clone()
        snap.meta["fit"] = {"next_step": step_done, "lr": lr, "adam": _as_lists(_adam_state(opt)), "best_loss": best_loss,
                            "best_step": best_step, "best_points": best_points.tolist(), "history": history,
                            "loss": loss if isinstance(loss, str) else "custom", "depth": depth, "size": target.size}
        save_ifs(snap, checkpoint)

    bar = tqdm(total=steps, initial=start, disable=not progress, desc="fit", unit="step")
    for step in range(start, steps):
        t0 = time.perf_counter()
        opt.zero_grad(set_to_none=True)
        reason = None
        try:
            field_ = distance_field(work, target.size, depth, method=method, device=device, gradient=gradient)
            value = loss_fn(field_, target, loss, sigma=sigma, levels=levels)
            if crossing_weight:
                value = value + crossing_weight * crossing_penalty(work, depth).to(value)
            if not torch.isfinite(value):
                reason = f"loss is {value.item()}"
            else:
                value.backward()
                if not torch.isfinite(work.points.grad).all():
                    reason = "gradient is not finite"
        except IFSError as exc:  # a rule became degenerate or non-contractive
            reason = str(exc)
        if reason is not None:
            # roll back to the points before the step that led here, and halve the learning rate
            with torch.no_grad():
                work.points.copy_(previous[0])
            lr *= 0.5
            _set_adam_state(opt, previous[1], lr)
            history["rollbacks"].append({"step": step, "reason": reason, "lr": lr})
            consecutive += 1
            if consecutive >= max_rollbacks:
                warnings.warn(f"fit stopped at step {step}: {consecutive} consecutive rolled-back steps ({reason})")
                bar.update(1)
                break
        else:
            consecutive = 0
            current = value.item()
            if current < best_loss:
                best_loss, best_step, best_points = current, step, work.points.detach().clone()
            previous = (work.points.detach().clone(), _adam_state(opt))
            if fixed:
                work.points.grad[fixed] = 0
            opt.step()
            history["step"].append(step)
            history["loss"].append(current)
            history["seconds"].append(time.perf_counter() - t0)
            if keep_every is not None and step % keep_every == 0:
                history["snapshots"]["step"].append(step)
                history["snapshots"]["points"].append(previous[0].tolist())
            if progress and step % 10 == 0:
                bar.set_postfix(loss=f"{current:.3g}")
        bar.update(1)
        if callback is not None:
            callback(step, history["loss"][-1] if history["loss"] else math.nan, work)
        if checkpoint is not None and (step + 1) % checkpoint_every == 0:
            save(step + 1)
    bar.close()
    if keep_every is not None:
        history["snapshots"]["step"].append(history["step"][-1] + 1 if history["step"] else start)
        history["snapshots"]["points"].append(work.points.detach().tolist())
    if checkpoint is not None:
        save(steps)
    history["cost"] = len(history["step"]) + len(history["rollbacks"])
    best = work.clone(best_points)
    best.meta["history"] = copy.deepcopy(history)
    final = work.clone()
    final.meta["history"] = copy.deepcopy(history)
    return FitResult(best, final, history, best_loss, best_step)
