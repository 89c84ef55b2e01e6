"""The descent: torch's Adam step for step, a failed step rolled back to before the step that led there at half the
rate, the best parameters kept, an early stop and clear errors."""
import pytest
import torch

from ifslib.core.fitting.descent import Descent, StepPolicy, converged
from ifslib.errors import IFSError


def quadratic(x: torch.Tensor):
    return lambda: ((x - torch.tensor([3.0, -1.0], dtype=x.dtype)) ** 2).sum()


def test_without_a_policy_it_is_torch_s_adam_bit_for_bit():
    x = torch.tensor([0.5, 0.2], dtype=torch.float64, requires_grad=True)
    y = x.detach().clone().requires_grad_(True)
    descent = Descent([{"params": [x], "lr": 0.1}], quadratic(x))
    assert descent.run(25) == "steps" and descent.index == 25 and len(descent.losses) == 25
    adam = torch.optim.Adam([y], lr=0.1)
    for _ in range(25):
        adam.zero_grad()
        quadratic(y)().backward()
        adam.step()
    assert torch.equal(x, y)


def test_a_failed_step_goes_back_to_before_the_step_that_led_there_at_half_the_rate():
    x = torch.tensor([0.0, 0.0], dtype=torch.float64, requires_grad=True)

    def loss():
        if x[0] > 0.25:
            raise IFSError("a rule became non-contractive")
        return quadratic(x)()

    descent = Descent([{"params": [x], "lr": 0.1}], loss, StepPolicy(rollback=True, max_rollbacks=50, keep_best=True))
    seen = []
    descent.run(40, after=lambda index, value: seen.append((index, value, x.detach().clone())))
    failed = [k for k, (_, value, _) in enumerate(seen) if value is None]
    assert failed
    first = failed[0]
    # the points after the rollback are those before the last good step (whose move led over the bound)
    assert torch.equal(seen[first][2], seen[first - 2][2])
    assert descent.rates[0] <= 0.05 and all(float(points[0]) <= 0.25 for k, (_, _, points) in enumerate(seen)
                                             if k + 1 < len(seen) and seen[k + 1][1] is not None)
    assert descent.best_loss == min(descent.losses) and descent.best_step not in failed


def test_consecutive_failures_stop_the_descent_with_a_warning():
    x = torch.tensor([1.0], requires_grad=True)
    policy = StepPolicy(rollback=True, max_rollbacks=3, name="probe")
    descent = Descent([{"params": [x], "lr": 0.1}], lambda: x.sum() * float("nan"), policy)
    with pytest.warns(UserWarning, match="probe stopped at step 2: 3 consecutive"):
        assert descent.run(10) == "rollbacks"
    assert descent.rates == [0.1 / 8] and descent.losses == [] and descent.reason.startswith("loss is nan")


def test_without_rollback_a_loss_that_is_not_finite_raises_the_advice():
    x = torch.tensor([1.0], requires_grad=True)
    descent = Descent([{"params": [x], "lr": 0.1}], lambda: x.sum() / 0 * 0, StepPolicy(advice="lower lr"))
    with pytest.raises(IFSError, match="lower lr"):
        descent.run(3)


def test_early_stop_and_the_schedule():
    x = torch.tensor([3.0, -1.0], dtype=torch.float64, requires_grad=True)   # at the minimum already
    policy = StepPolicy(tol=1e-3, patience=5, schedule=lambda index: 0.5)
    descent = Descent([{"params": [x], "lr": 0.2}], quadratic(x), policy)
    assert descent.run(100) == "converged" and descent.index == 6
    assert descent.adam.param_groups[0]["lr"] == 0.1
    assert converged([5.0, 4.0, 3.99, 3.99], 0.01, 2) and not converged([5.0, 4.0, 3.0], 0.01, 2)


def test_forget_and_bad_input():
    x = torch.ones(3, 2, requires_grad=True)
    descent = Descent([{"params": [x], "lr": 0.1}], lambda: (x ** 2).sum())
    descent.run(2)
    descent.forget(x, 1)
    assert (descent.adam.state[x]["exp_avg"][1] == 0).all() and (descent.adam.state[x]["exp_avg"][0] != 0).all()
    with pytest.raises(IFSError, match="StepPolicy"):
        Descent([{"params": [x], "lr": 0.1}], lambda: x.sum(), {"rollback": True})
    with pytest.raises(IFSError, match="max_rollbacks"):
        StepPolicy(max_rollbacks=0)
