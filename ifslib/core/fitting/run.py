"""One Adam run: the bottom of the fitting layer (a step that is not finite or breaks a map is rolled back)."""
from __future__ import annotations

import math
from typing import Callable

import torch
from tqdm.auto import tqdm

from ...errors import IFSError, check_int
from ...names import DEFAULT_STEPS
from ..geometry.crossings import check_curve, crossing_penalty
from ..geometry.ifs import IFS
from ..geometry.io import ifs_to_dict, load_ifs, save_ifs
from ...progress import draw_bars, note
from ..raster.distance import distance_field
from ..scoring.losses import loss as loss_fn
from ..targets.target import Target
from ...threads import refresh as refresh_threads
from .descent import Descent, StepPolicy
from .options import Checkpoint, RunOptions
from .result import FitResult, History


class _Run:
    """The state of one run: the descent on the points, and the history; one step at a time."""

    def __init__(self, ifs: IFS, target: Target, options: RunOptions, depth: int | str):
        self.target, self.options, self.depth = target, options, depth
        self.work = ifs.clone()
        fixed = list(self.work.fixed)

        def hold() -> None:  # the fixed points do not move
            self.work.points.grad[fixed] = 0

        policy = StepPolicy(rollback=True, max_rollbacks=options.max_rollbacks, keep_best=True, tol=options.tol,
                            patience=options.stop_window, gradient=hold if fixed else None, name="fit")
        self.descent = Descent([{"params": [self.work.points], "lr": options.step_lr}], self.loss, policy)
        self.history = History()
        self.descent.losses = self.history.loss  # one list: the descent appends each step's loss to the history

    def resume(self, path) -> None:
        """Continue from a checkpoint: the result equals that of an uninterrupted run."""
        saved = load_ifs(path)
        state = saved.meta.get("fit")
        if not state:
            raise IFSError(f"{path} is not a fit checkpoint (no 'fit' entry in its meta)")
        d = self.descent
        d.restore([saved.points], [state["adam"]])
        d.rates = [state["lr"]]
        d.index, d.best_loss, d.best_step = state["next_step"], state["best_loss"], state["best_step"]
        d.best = [torch.tensor(state["best_points"], dtype=self.work.points.dtype)]
        self.history = History.from_dict(state["history"])
        d.losses = self.history.loss  # the resumed history's list, as in __init__

    def loss(self) -> torch.Tensor:
        """The loss at the current points (the distance field against the target, and the crossings' penalty)."""
        o = self.options
        field_ = distance_field(self.work, self.target.size, self.depth, method=o.method, device=o.device,
                                gradient=o.gradient)
        value = loss_fn(field_, self.target, o.loss, sigma=o.sigma, levels=o.levels)
        if o.crossing_weight:
            value = value + o.crossing_weight * crossing_penalty(self.work, self.depth).to(value)
        return value

    def record(self, step: int, current: float | None) -> None:
        """The step in the history: its loss and time (and a snapshot of its points), or why it was rolled back."""
        h, d = self.history, self.descent
        if current is None:
            h.rollbacks.append({"step": step, "reason": d.reason, "lr": d.rates[0]})
            return
        h.step.append(step)
        h.seconds.append(d.seconds)
        every = self.options.keep_every
        if every is not None and step % every == 0:
            h.snapshots["step"].append(step)
            h.snapshots["points"].append(d.previous[0][0].tolist())

    def save(self, path, step_done: int) -> None:
        """Write the IFS with the optimizer state and history, atomically (`ifslib.save_ifs`)."""
        d = self.descent
        snap = self.work.clone()
        adam = {k: v.tolist() if isinstance(v, torch.Tensor) else v for k, v in d.snapshot()[1][0].items()}
        loss = self.options.loss
        snap.meta["fit"] = {"next_step": step_done, "lr": d.rates[0], "adam": adam, "best_loss": d.best_loss,
                            "best_step": d.best_step, "best_points": d.best[0].tolist(),
                            "history": self.history.to_dict(), "loss": loss if isinstance(loss, str) else "custom",
                            "depth": self.depth, "size": self.target.size}
        save_ifs(snap, path)

    def result(self) -> FitResult:
        d = self.descent
        best = self.work.clone(d.best[0])
        return FitResult(best, self.work.clone(), self.history, d.best_loss, d.best_step).record()


def run(ifs: IFS, target: Target, *, steps: int = DEFAULT_STEPS, options: RunOptions = RunOptions(), seed: int = 0,
        callback: Callable | None = None, checkpoint: Checkpoint | None = None, progress: bool = True,
        desc: str | None = None) -> FitResult:
    """One Adam run on the control points at the target's size, seeded by ``seed``, for at most ``steps`` steps,
    resumable by ``checkpoint``; ``history.stopped`` says why it ended."""
    check_int(steps, "steps", 0)
    if options.crossing_weight:
        check_curve(ifs, "crossing_weight")
    depth = ifs.depth if options.depth is None else options.depth
    refresh_threads()  # in auto mode: the cores free now, at every run (each stage of a strategy)
    torch.manual_seed(seed)
    state = _Run(ifs, target, options, depth)
    if checkpoint is not None and checkpoint.resume is not None:
        state.resume(checkpoint.resume)
    history, descent = state.history, state.descent
    start = descent.index
    if options.keep_every is not None and history.snapshots is None:
        history.pattern = ifs_to_dict(ifs)
        history.snapshots = {"step": [], "points": []}
    desc = f"fit · {target.size}²" if desc is None else desc
    # a live bar on a terminal (or in Jupyter); in a log, one line when the run ends (see ifslib.progress)
    live = progress and draw_bars()
    bar = tqdm(total=steps, initial=start, disable=not live, desc=desc, unit="step")

    def after(step: int, current: float | None) -> None:
        state.record(step, current)
        if callback is not None:
            callback(step, history.loss[-1] if history.loss else math.nan, state.work)
        if checkpoint is not None and checkpoint.path is not None and (step + 1) % checkpoint.every == 0:
            state.save(checkpoint.path, step + 1)

    stopped = descent.run(steps, after, bar)
    if stopped == "rollbacks":
        state.record(descent.index - 1, None)
    bar.close()
    step = descent.index
    if progress and (stopped != "steps" or not live):
        how = {"converged": f"converged at step {step} of {steps}", "steps": f"ran its {steps} steps",
               "rollbacks": f"stopped at step {step} of {steps} (rolled-back steps)"}[stopped]
        note(f"{desc}: {how} (best loss {descent.best_loss:.4g} at step {descent.best_step})")
    if options.keep_every is not None:
        history.snapshots["step"].append(history.step[-1] + 1 if history.step else start)
        history.snapshots["points"].append(state.work.points.detach().tolist())
    if checkpoint is not None and checkpoint.path is not None:
        state.save(checkpoint.path, step if stopped == "converged" else steps)
    history.stopped = stopped
    history.cost = len(history.step) + len(history.rollbacks)
    return state.result()
