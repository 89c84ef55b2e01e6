"""The descent: the one Adam loop the library's fits run, each handing it its parameters and its loss (the other,
benchmarks/batch.py's, keeps a step count and learning rate per item, which torch's Adam cannot)."""
from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass
from typing import Callable, Sequence

import torch

from ...errors import IFSError, LeafBudgetError, check_int


def converged(losses: list[float], tol: float, patience: int) -> bool:
    """Whether a descent has converged: its best loss improved by at most a fraction ``tol`` over the last
    ``patience`` steps.

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


@dataclass(frozen=True)
class StepPolicy:
    """What a `Descent` does around each Adam step.

    Attributes
    ----------
    rollback : bool
        A step whose loss or gradient is not finite, or whose loss raises `IFSError` (a rule became
        degenerate or non-contractive), is undone: the parameters and Adam's state go back to before
        the step that led there, at half the learning rate. False: a loss that is not finite raises
        `IFSError` with ``advice``.
    max_rollbacks : int
        With ``rollback``: this many consecutive rolled-back steps stop the descent.
    keep_best : bool
        Keep the parameters of the least loss so far (`Descent.best`).
    tol, patience : float and int, optional
        Stop early once the best loss improved by at most a fraction ``tol`` over the last
        ``patience`` steps (`converged`); ``tol`` None never stops early.
    gradient : callable, optional
        ``gradient()`` edits the gradients in place before Adam's step (holds fixed points).
    schedule : callable, optional
        ``schedule(index)``: the share of each group's learning rate at step ``index`` (a decay).
    contract : callable, optional
        ``contract(before)``, without gradients, after Adam's step: moves the parameters back into
        the contractive maps, given their values ``before`` the step (`ifslib.automatic.fractal.collage.clamp_scales`,
        `ifslib.measures.measure_fit.halve_step`).
    advice : str
        Without rollback: what the error raised by a loss that is not finite tells the caller.
    name : str
        The descent's name in its warning when rolled-back steps stop it.
    """

    rollback: bool = False
    max_rollbacks: int = 10
    keep_best: bool = False
    tol: float | None = None
    patience: int = 50
    gradient: Callable[[], None] | None = None
    schedule: Callable[[int], float] | None = None
    contract: Callable[[list[torch.Tensor]], None] | None = None
    advice: str = "the loss is not finite: lower the learning rate"
    name: str = "descent"

    def __post_init__(self):
        check_int(self.max_rollbacks, "max_rollbacks", 1)
        check_int(self.patience, "patience", 1)


class Descent:
    """Adam on parameter groups and a loss, one step at a time under a `StepPolicy`.

    Parameters
    ----------
    groups : sequence of dict
        torch's parameter groups, each ``{"params": [tensors], "lr": rate}``.
    loss : callable
        ``loss()``: the loss at the current parameters, a scalar tensor (may be replaced between runs:
        the splat fit's levels).
    policy : StepPolicy

    Attributes
    ----------
    index : int
        The steps taken, rolled-back ones included (the index of the next step).
    losses, rates : list of float
        The loss of every step not rolled back; each group's learning rate (halved by each rollback).
    best, best_loss, best_step
        With ``policy.keep_best``: the parameters of the least loss, that loss and its step.
    previous, reason
        With ``policy.rollback``: a `snapshot` from before the last step not rolled back; why the last step
        was rolled back (None when it was not).
    """

    def __init__(self, groups: Sequence[dict], loss: Callable[[], torch.Tensor], policy: StepPolicy = StepPolicy()):
        if not isinstance(policy, StepPolicy):
            raise IFSError(f"policy must be a StepPolicy, got {type(policy).__name__}")
        self.loss, self.policy = loss, policy
        self.adam = torch.optim.Adam([dict(g) for g in groups])
        self.params = [p for g in self.adam.param_groups for p in g["params"]]
        self.rates = [g["lr"] for g in self.adam.param_groups]
        self.index, self.losses, self.consecutive, self.reason, self.seconds = 0, [], 0, None, 0.0
        self.best_loss, self.best_step = math.inf, -1
        self.best = [p.detach().clone() for p in self.params]
        self.previous = self.snapshot() if policy.rollback else None

    def snapshot(self) -> tuple[list[torch.Tensor], list[dict]]:
        """Copies of the parameters and of Adam's state for each (``{}`` before its first step)."""
        states = [{k: v.clone() if k != "step" else float(v) for k, v in self.adam.state[p].items()}
                  for p in self.params]
        return [p.detach().clone() for p in self.params], states

    def restore(self, values: list, states: list[dict]) -> None:
        """Set the parameters to ``values`` and Adam's states to ``states`` (a `snapshot`, its tensors maybe lists)."""
        with torch.no_grad():
            for p, v in zip(self.params, values):
                p.copy_(torch.as_tensor(v).to(p.dtype))
        for p, saved in zip(self.params, states):
            self.adam.state.pop(p, None)
            if saved:
                self.adam.state[p] = {"step": torch.tensor(saved["step"]),
                                      **{k: torch.as_tensor(saved[k], dtype=p.dtype).clone()
                                         for k in ("exp_avg", "exp_avg_sq")}}

    def forget(self, param: torch.Tensor, rows) -> None:
        """Reset Adam's moments of ``param[rows]`` (where they were learnt says nothing of where the rows now are)."""
        state = self.adam.state.get(param, {})
        for key in ("exp_avg", "exp_avg_sq"):
            if key in state:
                state[key][rows] = 0

    def _evaluate(self) -> tuple[torch.Tensor | None, str | None]:
        """The loss with its gradients, or why the step must be rolled back."""
        if not self.policy.rollback:
            value = self.loss()
            if not torch.isfinite(value):
                raise IFSError(self.policy.advice)
            value.backward()
            return value, None
        try:
            value = self.loss()
            if not torch.isfinite(value):
                return value, f"loss is {value.item()}"
            value.backward()
            if not all(bool(torch.isfinite(p.grad).all()) for p in self.params if p.grad is not None):
                return value, "gradient is not finite"
            return value, None
        except LeafBudgetError:
            raise  # not a bad step: the attractor's cut is too fine for the budget at any parameters near these
        except IFSError as exc:  # a rule became degenerate or non-contractive
            return None, str(exc)

    def step(self) -> float | None:
        """One step: the loss at the parameters, then Adam's step; returns the loss, or None when rolled back."""
        policy, t0 = self.policy, time.perf_counter()
        self.adam.zero_grad(set_to_none=True)
        value, self.reason = self._evaluate()
        self.index += 1
        if self.reason is not None:  # back to before the step that led here, at half the rate
            self.restore(*self.previous)
            self.rates = [rate * 0.5 for rate in self.rates]
            self.consecutive += 1
            return None
        self.consecutive = 0
        current = value.item()
        if policy.keep_best and current < self.best_loss:
            self.best_loss, self.best_step = current, self.index - 1
            self.best = [p.detach().clone() for p in self.params]
        if policy.rollback:
            self.previous = self.snapshot()
        if policy.gradient is not None:
            policy.gradient()
        before = [p.detach().clone() for p in self.params] if policy.contract is not None else None
        share = None if policy.schedule is None else policy.schedule(self.index - 1)
        for group, rate in zip(self.adam.param_groups, self.rates):
            group["lr"] = rate if share is None else rate * share
        self.adam.step()
        if policy.contract is not None:
            with torch.no_grad():
                policy.contract(before)
        self.losses.append(current)
        self.seconds = time.perf_counter() - t0
        return current

    def run(self, steps: int, after: Callable[[int, float | None], None] | None = None, bar=None) -> str:
        """Take steps until ``steps`` have been taken in all (those of earlier runs count); ``after(index, loss)``
        follows each (``loss`` None when it was rolled back), and ``bar`` (tqdm) is advanced by one a step.

        Returns why it stopped: ``"steps"``, ``"converged"`` (``policy.tol``) or ``"rollbacks"``
        (``policy.max_rollbacks`` consecutive rolled-back steps, with a warning).
        """
        policy = self.policy
        for index in range(self.index, steps):
            current = self.step()
            if bar is not None:
                if current is not None and index % 10 == 0:
                    bar.set_postfix(loss=f"{current:.3g}")
                bar.update(1)
            if current is None and self.consecutive >= policy.max_rollbacks:
                warnings.warn(f"{policy.name} stopped at step {index}: {self.consecutive} consecutive rolled-back "
                              f"steps ({self.reason})")
                return "rollbacks"
            if after is not None:
                after(index, current)
            if policy.tol is not None and current is not None and converged(self.losses, policy.tol, policy.patience):
                return "converged"
        return "steps"


__all__ = ["Descent", "StepPolicy", "converged"]
