"""One Adam run: the bottom of the fitting layer.

`run` moves an IFS's control points so that its rendering matches a target at one size. Each step
renders the distance field (exact nearest leaf, exact gradient), takes a loss against the target,
and lets Adam move the points. A step whose loss or gradient is not finite, or whose points make a
rule degenerate or non-contractive, is rolled back (the points and the optimizer go back to before
the step that led there, the learning rate is halved) and reported in the history instead of
poisoning the points. ``steps`` is a budget: with ``tol`` set, the run stops once its best loss has
stopped improving (see `converged`). Strategies (`ifslib.fitting.strategies`) are built on it, and
the public `ifslib.fit` on them; nothing here knows of either.
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
from ..errors import IFSError, LeafBudgetError, check_int
from ..progress import draw_bars, note
from ..threads import refresh as refresh_threads
from ..geometry.attractor import check_depth_or_attractor
from ..geometry.ifs import IFS
from ..geometry.io import ifs_to_dict, load_ifs, save_ifs
from ..scoring.losses import loss as loss_fn
from ..targets.target import Target


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


def converged(losses: list[float], tol: float, patience: int) -> bool:
    """Whether a run has converged: its best loss improved by at most a fraction ``tol`` over the last ``patience`` steps.

    Parameters
    ----------
    losses : list of float
        The loss at every step so far (``history["loss"]``).
    tol : float
        Relative improvement of the best loss that still counts as progress.
    patience : int
        Window, in steps.

    Returns
    -------
    bool
        False while fewer than ``patience + 1`` losses are known.
    """
    if len(losses) <= patience:
        return False
    before = min(losses[:-patience])
    return before - min(losses[-patience:]) <= tol * abs(before)


def check_stop(tol: float | None, patience: int) -> None:
    """Raise `IFSError` unless ``tol`` is None or a finite number >= 0 and ``patience`` an int >= 1."""
    if tol is not None and not (isinstance(tol, (int, float)) and not isinstance(tol, bool) and tol >= 0
                                and math.isfinite(tol)):
        raise IFSError(f"tol must be None or a finite number >= 0, got {tol!r}")
    check_int(patience, "patience", 1)


def run(ifs: IFS, target: Target, steps: int = 1500, lr: float = 0.003, loss: str | Callable = "multiscale_pixel",
        depth: int | None = None, seed: int = 0, callback: Callable | None = None, checkpoint: str | Path | None = None,
        checkpoint_every: int = 100, resume: str | Path | None = None, progress: bool = True,
        sigma: float | None = None, levels: int = 5, method: str = "fast", device: str = "auto",
        gradient: str = "exact", max_rollbacks: int = 20, keep_every: int | None = None,
        crossing_weight: float = 0.0, tol: float | None = None, patience: int = 50,
        desc: str | None = None) -> FitResult:
    """One Adam run on the control points at the target's size.

    Parameters
    ----------
    ifs : IFS
        The starting point (not modified).
    target : Target
        Its size sets the render size.
    steps : int
        At most this many Adam steps (the paper used 1500).
    lr : float
        Learning rate (the paper used 0.003).
    loss : str or callable
        ``pixel``, ``multiscale_pixel``, ``distance``, ``multiscale_distance`` or ``f(distance, target)``.
    depth : int or "attractor", optional
        Render depth (``ifs.depth`` when None); ``"attractor"`` fits the attractor itself (its
        depth-free distance, `ifslib.distance_field`).
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
        Show a tqdm progress bar labelled ``desc``, with the current loss, when standard error is a
        terminal (or in Jupyter), and say in one line when a run stops early; elsewhere (a log
        file, a pipe) only one line when the run ends (`ifslib.progress`).
    sigma, levels
        Passed to the loss.
    method, device, gradient
        Passed to `ifslib.distance_field` (``gradient="paper"`` reproduces the paper's cut gradient).
    max_rollbacks : int
        Stop after this many consecutive rolled-back steps.
    keep_every : int, optional
        Keep the control points every ``keep_every`` steps (and after the last step) in
        ``history["snapshots"]``, with the pattern in ``history["pattern"]``, for `ifslib.animate`.
    crossing_weight : float
        For curves: add ``crossing_weight * ifslib.crossings.crossing_penalty(ifs)`` to the loss.
    tol, patience
        Early stop: end the run once `converged` (the best loss improved by at most a fraction
        ``tol`` over the last ``patience`` steps). None (the default) runs every step.
    desc : str, optional
        The progress bar's label (strategies name the stage: probe, size); ``"fit · <size>²"`` when None.

    Returns
    -------
    FitResult
        ``history["stopped"]`` says why the run ended: ``"steps"`` (the budget was spent),
        ``"converged"`` or ``"rollbacks"``.
    """
    check_int(steps, "steps", 0)
    check_stop(tol, patience)
    if not (isinstance(crossing_weight, (int, float)) and crossing_weight >= 0 and math.isfinite(crossing_weight)):
        raise IFSError(f"crossing_weight must be a finite number >= 0, got {crossing_weight!r}")
    if crossing_weight:
        check_curve(ifs, "crossing_weight")
    if keep_every is not None:
        check_int(keep_every, "keep_every", 1)
    if not (isinstance(lr, (int, float)) and lr > 0 and math.isfinite(lr)):
        raise IFSError(f"lr must be a finite number > 0, got {lr!r}")
    depth = ifs.depth if depth is None else check_depth_or_attractor(depth)
    refresh_threads()  # in auto mode: the cores free now, at every run (each stage of a strategy)
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

    desc = f"fit · {target.size}²" if desc is None else desc
    # a live bar on a terminal (or in Jupyter); in a log, one line when the run ends (see ifslib.progress)
    live = progress and draw_bars()
    bar = tqdm(total=steps, initial=start, disable=not live, desc=desc, unit="step")
    stopped = "steps"
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
        except LeafBudgetError:
            raise  # not a bad step: the attractor's cut is too fine for the budget at any points near these
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
                stopped = "rollbacks"
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
        if tol is not None and reason is None and converged(history["loss"], tol, patience):
            stopped = "converged"
            break
    bar.close()
    if progress and (stopped != "steps" or not live):
        how = {"converged": f"converged at step {step + 1} of {steps}", "steps": f"ran its {steps} steps",
               "rollbacks": f"stopped at step {step + 1} of {steps} (rolled-back steps)"}[stopped]
        note(f"{desc}: {how} (best loss {best_loss:.4g} at step {best_step})")
    if keep_every is not None:
        history["snapshots"]["step"].append(history["step"][-1] + 1 if history["step"] else start)
        history["snapshots"]["points"].append(work.points.detach().tolist())
    if checkpoint is not None:
        save(step + 1 if stopped == "converged" else steps)
    history["stopped"] = stopped
    history["cost"] = len(history["step"]) + len(history["rollbacks"])
    best = work.clone(best_points)
    best.meta["history"] = copy.deepcopy(history)
    final = work.clone()
    final.meta["history"] = copy.deepcopy(history)
    return FitResult(best, final, history, best_loss, best_step)
