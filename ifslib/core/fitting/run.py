"""One Adam run: the bottom of the fitting layer.

`run` moves an IFS's control points so that its rendering matches a target at one size. Each step
renders the distance field (exact nearest leaf, exact gradient), takes a loss against the target,
and lets Adam move the points. A step whose loss or gradient is not finite, or whose points make a
rule degenerate or non-contractive, is rolled back (the points and the optimizer go back to before
the step that led there, the learning rate is halved) and reported in the history instead of
poisoning the points. ``steps`` is a budget: with ``tol`` set, the run stops once its best loss has
stopped improving (see `converged`). Strategies (`ifslib.core.fitting.strategies`) are built on it, and
the public `ifslib.fit` on them; nothing here knows of either.
"""
from __future__ import annotations

import math
import time
import warnings
from typing import Callable

import torch
from tqdm.auto import tqdm

from ...errors import IFSError, LeafBudgetError, check_int
from ...names import DEFAULT_STEPS
from ..geometry.crossings import check_curve, crossing_penalty
from ..geometry.ifs import IFS
from ..geometry.io import ifs_to_dict, load_ifs, save_ifs
from ...progress import draw_bars, note
from ..raster.distance import distance_field
from ..scoring.losses import loss as loss_fn
from ..targets.target import Target
from ...threads import refresh as refresh_threads
from .options import Checkpoint, RunOptions
from .result import FitResult, History


def converged(losses: list[float], tol: float, patience: int) -> bool:
    """Whether a run has converged: its best loss improved by at most a fraction ``tol`` over the last ``patience`` steps.

    Parameters
    ----------
    losses : list of float
        The loss at every step so far (``history.loss``).
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


def _adam_state(opt: torch.optim.Adam) -> dict:
    """A copy of Adam's state for the one parameter (tensors)."""
    state = opt.state[opt.param_groups[0]["params"][0]]
    if not state:
        return {}
    return {"step": float(state["step"]), "exp_avg": state["exp_avg"].clone(), "exp_avg_sq": state["exp_avg_sq"].clone()}


def _set_adam_state(opt: torch.optim.Adam, saved: dict, lr: float) -> None:
    param = opt.param_groups[0]["params"][0]
    opt.param_groups[0]["lr"] = lr
    opt.state.clear()
    if saved:
        opt.state[param] = {"step": torch.tensor(saved["step"]),
                            "exp_avg": torch.as_tensor(saved["exp_avg"], dtype=param.dtype).clone(),
                            "exp_avg_sq": torch.as_tensor(saved["exp_avg_sq"], dtype=param.dtype).clone()}


class _Run:
    """The state of one run: the points, Adam, the best points so far and the history; one step at a time."""

    def __init__(self, ifs: IFS, target: Target, options: RunOptions, depth: int | str):
        self.target, self.options, self.depth = target, options, depth
        self.work = ifs.clone()
        self.fixed = list(self.work.fixed)
        self.lr = options.step_lr
        self.opt = torch.optim.Adam([self.work.points], lr=self.lr)
        self.history = History()
        self.start, self.best_loss, self.best_step = 0, math.inf, -1
        self.best_points = self.work.points.detach().clone()
        self.previous = (self.work.points.detach().clone(), _adam_state(self.opt))
        self.consecutive = 0

    def resume(self, path) -> None:
        """Continue from a checkpoint: the result equals that of an uninterrupted run."""
        saved = load_ifs(path)
        state = saved.meta.get("fit")
        if not state:
            raise IFSError(f"{path} is not a fit checkpoint (no 'fit' entry in its meta)")
        with torch.no_grad():
            self.work.points.copy_(saved.points.to(self.work.points.dtype))
        self.lr = state["lr"]
        _set_adam_state(self.opt, state["adam"], self.lr)
        self.start, self.best_loss, self.best_step = state["next_step"], state["best_loss"], state["best_step"]
        self.best_points = torch.tensor(state["best_points"], dtype=self.work.points.dtype)
        self.history = History.from_dict(state["history"])

    def evaluate(self) -> tuple[torch.Tensor | None, str | None]:
        """The loss at the current points, with its gradient; or why the step must be rolled back."""
        o = self.options
        try:
            field_ = distance_field(self.work, self.target.size, self.depth, method=o.method, device=o.device,
                                    gradient=o.gradient)
            value = loss_fn(field_, self.target, o.loss, sigma=o.sigma, levels=o.levels)
            if o.crossing_weight:
                value = value + o.crossing_weight * crossing_penalty(self.work, self.depth).to(value)
            if not torch.isfinite(value):
                return value, f"loss is {value.item()}"
            value.backward()
            if not torch.isfinite(self.work.points.grad).all():
                return value, "gradient is not finite"
            return value, None
        except LeafBudgetError:
            raise  # not a bad step: the attractor's cut is too fine for the budget at any points near these
        except IFSError as exc:  # a rule became degenerate or non-contractive
            return None, str(exc)

    def rollback(self, step: int, reason: str) -> None:
        """Back to the points before the step that led here, at half the learning rate."""
        with torch.no_grad():
            self.work.points.copy_(self.previous[0])
        self.lr *= 0.5
        _set_adam_state(self.opt, self.previous[1], self.lr)
        self.history.rollbacks.append({"step": step, "reason": reason, "lr": self.lr})
        self.consecutive += 1

    def advance(self, step: int, value: torch.Tensor, seconds_from: float) -> float:
        """Keep the best points, remember these as the last good ones, and take Adam's step; returns the loss."""
        self.consecutive = 0
        current = value.item()
        if current < self.best_loss:
            self.best_loss, self.best_step, self.best_points = current, step, self.work.points.detach().clone()
        self.previous = (self.work.points.detach().clone(), _adam_state(self.opt))
        if self.fixed:
            self.work.points.grad[self.fixed] = 0
        self.opt.step()
        h = self.history
        h.step.append(step)
        h.loss.append(current)
        h.seconds.append(time.perf_counter() - seconds_from)
        every = self.options.keep_every
        if every is not None and step % every == 0:
            h.snapshots["step"].append(step)
            h.snapshots["points"].append(self.previous[0].tolist())
        return current

    def save(self, path, step_done: int) -> None:
        """Write the IFS with the optimizer state and history, atomically (`ifslib.save_ifs`)."""
        snap = self.work.clone()
        adam = {k: v.tolist() if isinstance(v, torch.Tensor) else v for k, v in _adam_state(self.opt).items()}
        loss = self.options.loss
        snap.meta["fit"] = {"next_step": step_done, "lr": self.lr, "adam": adam, "best_loss": self.best_loss,
                            "best_step": self.best_step, "best_points": self.best_points.tolist(),
                            "history": self.history.to_dict(), "loss": loss if isinstance(loss, str) else "custom",
                            "depth": self.depth, "size": self.target.size}
        save_ifs(snap, path)

    def result(self) -> FitResult:
        best = self.work.clone(self.best_points)
        return FitResult(best, self.work.clone(), self.history, self.best_loss, self.best_step).record()


def run(ifs: IFS, target: Target, *, steps: int = DEFAULT_STEPS, options: RunOptions = RunOptions(), seed: int = 0,
        callback: Callable | None = None, checkpoint: Checkpoint | None = None, progress: bool = True,
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
    options : RunOptions
        The loss, learning rate, depth, early stop and the rest (`ifslib.core.fitting.options.RunOptions`).
    seed : int
        Seeds torch before the loop; a seeded run on CPU is reproducible.
    callback : callable, optional
        ``callback(step, loss, ifs)`` after every step.
    checkpoint : Checkpoint, optional
        Write the state every ``checkpoint.every`` steps and at the end; continue from ``checkpoint.resume``.
    progress : bool
        A tqdm bar labelled ``desc`` when standard error is a terminal (or in Jupyter), and one
        line when a run stops early; elsewhere (a log file, a pipe) one line when the run ends.
    desc : str, optional
        The progress bar's label (strategies name the stage); ``"fit · <size>²"`` when None.

    Returns
    -------
    FitResult
        ``history.stopped`` says why the run ended: ``"steps"``, ``"converged"`` or ``"rollbacks"``.
    """
    check_int(steps, "steps", 0)
    if options.crossing_weight:
        check_curve(ifs, "crossing_weight")
    depth = ifs.depth if options.depth is None else options.depth
    patience = options.stop_window
    refresh_threads()  # in auto mode: the cores free now, at every run (each stage of a strategy)
    torch.manual_seed(seed)
    state = _Run(ifs, target, options, depth)
    if checkpoint is not None and checkpoint.resume is not None:
        state.resume(checkpoint.resume)
    history = state.history
    if options.keep_every is not None and history.snapshots is None:
        history.pattern = ifs_to_dict(ifs)
        history.snapshots = {"step": [], "points": []}
    desc = f"fit · {target.size}²" if desc is None else desc
    # a live bar on a terminal (or in Jupyter); in a log, one line when the run ends (see ifslib.progress)
    live = progress and draw_bars()
    bar = tqdm(total=steps, initial=state.start, disable=not live, desc=desc, unit="step")
    stopped, step = "steps", state.start
    for step in range(state.start, steps):
        t0 = time.perf_counter()
        state.opt.zero_grad(set_to_none=True)
        value, reason = state.evaluate()
        if reason is not None:
            state.rollback(step, reason)
            if state.consecutive >= options.max_rollbacks:
                warnings.warn(f"fit stopped at step {step}: {state.consecutive} consecutive rolled-back steps ({reason})")
                bar.update(1)
                stopped = "rollbacks"
                break
        else:
            current = state.advance(step, value, t0)
            if progress and step % 10 == 0:
                bar.set_postfix(loss=f"{current:.3g}")
        bar.update(1)
        if callback is not None:
            callback(step, history.loss[-1] if history.loss else math.nan, state.work)
        if checkpoint is not None and checkpoint.path is not None and (step + 1) % checkpoint.every == 0:
            state.save(checkpoint.path, step + 1)
        if options.tol is not None and reason is None and converged(history.loss, options.tol, patience):
            stopped = "converged"
            break
    bar.close()
    if progress and (stopped != "steps" or not live):
        how = {"converged": f"converged at step {step + 1} of {steps}", "steps": f"ran its {steps} steps",
               "rollbacks": f"stopped at step {step + 1} of {steps} (rolled-back steps)"}[stopped]
        note(f"{desc}: {how} (best loss {state.best_loss:.4g} at step {state.best_step})")
    if options.keep_every is not None:
        history.snapshots["step"].append(history.step[-1] + 1 if history.step else state.start)
        history.snapshots["points"].append(state.work.points.detach().tolist())
    if checkpoint is not None and checkpoint.path is not None:
        state.save(checkpoint.path, step + 1 if stopped == "converged" else steps)
    history.stopped = stopped
    history.cost = len(history.step) + len(history.rollbacks)
    return state.result()
