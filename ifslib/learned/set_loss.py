"""The permutation-invariant set loss: each true map matched to one slot by the Hungarian method, so that the
order in which a guess lists its maps never costs."""
from __future__ import annotations

import numpy as np
import torch
import torch.nn.functional as F
from scipy.optimize import linear_sum_assignment

from . import config

#: A map's six numbers' weights: the linear part's entries (rows ``a b``, ``c d``) and the shift ``e, f``.
WEIGHTS = torch.tensor([[config.LINEAR_WEIGHT] * 2 + [1.0]] * 2)


def map_costs(guessed: torch.Tensor, true: torch.Tensor) -> torch.Tensor:
    """``(..., k, m)``: the weighted L1 distance between each of ``k`` guessed maps and ``m`` true maps
    ``(..., k or m, 2, 3)``."""
    return ((guessed[..., :, None, :, :] - true[..., None, :, :, :]).abs() * WEIGHTS.to(guessed)).sum((-1, -2))


def match(guessed: torch.Tensor, true: torch.Tensor) -> tuple[np.ndarray, np.ndarray]:
    """Slots and true maps paired at least total cost (`scipy.optimize.linear_sum_assignment`)."""
    return linear_sum_assignment(map_costs(guessed.detach(), true).cpu().numpy())


def set_loss(guessed: torch.Tensor, logits: torch.Tensor, truths: list[torch.Tensor],
             presence_weight: float = config.PRESENCE_WEIGHT, anchors: torch.Tensor | None = None) -> torch.Tensor:
    """The batch's mean set loss: the matched maps' weighted L1 per true map, plus ``presence_weight`` times the
    presence scores' binary cross-entropy (a matched slot present, weighted `config.PRESENT_WEIGHT`; the others
    absent).

    ``guessed``: ``(B, K, 2, 3)``; ``logits``: ``(B, K)``; ``truths``: B tensors ``(m_b, 2, 3)``, ``m_b <= K``.
    ``anchors``: ``(K, 2)``, the slots' places: matching then also costs `config.ANCHOR_WEIGHT` times the L1
    distance from a slot's anchor to a true map's shift, so that a map goes to the slot where its copy is centred
    and the presence scores learn one place a copy, not whichever neighbour guessed closest.
    """
    count = max(len(t) for t in truths)
    padded = guessed.new_zeros(len(truths), count, 2, 3)
    for b, true in enumerate(truths):
        padded[b, :len(true)] = true
    costs = map_costs(guessed.detach(), padded)                      # (B, K, count): one product for the batch
    if anchors is not None:
        costs = costs + config.ANCHOR_WEIGHT * (anchors[None, :, None] - padded[:, None, :, :, 2]).abs().sum(-1)
    costs = costs.cpu().numpy()
    batch, slots, maps, share = [], [], [], []
    for b, true in enumerate(truths):
        rows, cols = linear_sum_assignment(costs[b, :, :len(true)])
        batch += [b] * len(rows)
        slots += rows.tolist()
        maps += cols.tolist()
        share += [1.0 / len(true)] * len(rows)
    batch, slots, maps = (torch.tensor(v, device=guessed.device) for v in (batch, slots, maps))
    errors = ((guessed[batch, slots] - padded[batch, maps]).abs() * WEIGHTS.to(guessed)).sum((-1, -2))
    present = torch.zeros_like(logits)
    present[batch, slots] = 1.0
    presence = F.binary_cross_entropy_with_logits(logits, present, reduction="none",
                                                  pos_weight=logits.new_tensor(config.PRESENT_WEIGHT)).mean(1)
    return ((errors * errors.new_tensor(share)).sum() + presence_weight * presence.sum()) / len(truths)
