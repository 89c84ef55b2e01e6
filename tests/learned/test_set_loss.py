"""The set loss: the Hungarian matching is the cheapest of every order, and the maps' order never costs."""
import itertools

import numpy as np
import pytest
import torch

from ifslib.learned.set_loss import map_costs, match, set_loss


def brute_force(cost: np.ndarray) -> float:
    """The least total cost of matching every column (a true map) to a distinct row (a slot), by every order."""
    k, m = cost.shape
    return min(sum(cost[rows[j], j] for j in range(m)) for rows in itertools.permutations(range(k), m))


@pytest.mark.parametrize("k, m, seed", [(4, 4, 0), (6, 3, 1), (7, 5, 2), (5, 1, 3)])
def test_matching_is_the_cheapest_of_every_order(k, m, seed):
    g = torch.Generator().manual_seed(seed)
    guessed, true = torch.randn(k, 2, 3, generator=g), torch.randn(m, 2, 3, generator=g)
    rows, cols = match(guessed, true)
    cost = map_costs(guessed, true).numpy()
    assert len(set(rows.tolist())) == m and sorted(cols.tolist()) == list(range(m))
    assert cost[rows, cols].sum() == pytest.approx(brute_force(cost), rel=1e-6)


def test_the_order_of_the_true_maps_and_of_the_slots_never_costs():
    g = torch.Generator().manual_seed(4)
    guessed, logits = torch.randn(2, 6, 2, 3, generator=g), torch.randn(2, 6, generator=g)
    truths = [torch.randn(4, 2, 3, generator=g), torch.randn(6, 2, 3, generator=g)]
    loss = set_loss(guessed, logits, truths)
    turned = [t[torch.randperm(len(t), generator=g)] for t in truths]
    slots = torch.randperm(6, generator=g)
    assert float(set_loss(guessed, logits, turned)) == pytest.approx(float(loss), rel=1e-6)
    assert float(set_loss(guessed[:, slots], logits[:, slots], truths)) == pytest.approx(float(loss), rel=1e-6)


def test_a_perfect_guess_costs_only_its_presence_and_gradients_reach_every_output():
    true = torch.randn(3, 2, 3, generator=torch.Generator().manual_seed(5))
    guessed = torch.cat([true, torch.zeros(2, 2, 3)])[None].requires_grad_(True)
    sure = torch.tensor([[20.0, 20, 20, -20, -20]], requires_grad=True)
    assert float(set_loss(guessed, sure, [true])) < 1e-6
    unsure = torch.zeros(1, 5, requires_grad=True)
    set_loss(guessed + 0.1, unsure, [true]).backward()
    assert (guessed.grad[0, :3] != 0).all() and (guessed.grad[0, 3:] == 0).all() and (unsure.grad != 0).all()


def test_with_anchors_a_map_goes_to_the_slot_where_its_copy_is_centred():
    anchors = torch.tensor([[-0.25, 0.25], [0.25, 0.25], [-0.25, -0.25], [0.25, -0.25]])
    true = torch.zeros(1, 2, 3)
    true[0, :, 2] = torch.tensor([0.2, -0.3])
    same = torch.zeros(1, 4, 2, 3)                     # every slot guesses the same map: only the anchors differ
    logits = torch.zeros(1, 4, requires_grad=True)
    set_loss(same, logits, [true], anchors=anchors).backward()
    assert int(logits.grad[0].argmin()) == 3           # the slot of anchor (0.25, -0.25) is pushed to present
