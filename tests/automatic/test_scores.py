"""`ifslib.automatic.fractal.scores`: each pruning's bound is a lower bound of its score, and the scores are the
search's documented formulas."""
from dataclasses import replace

import numpy as np
import pytest

from ifslib.automatic.fractal import DEFAULT
from ifslib.automatic.fractal.scores import choice_score, least_choice_score, least_trial_score, trial_score


@pytest.mark.parametrize("config", [DEFAULT, replace(DEFAULT, map_cost=0.25, chamfer_cost=0.7)])
def test_the_bounds_are_lower_bounds_reached_at_a_perfect_attractor(config):
    rng = np.random.default_rng(0)
    for k in range(1, config.max_maps + 1):
        ious, chamfers = rng.uniform(0, 1, 200), rng.exponential(3.0, 200)
        assert all(choice_score(float(i), k, config) >= least_choice_score(k, config) for i in ious)
        assert all(trial_score(float(c), k, config) >= least_trial_score(k, config) for c in chamfers)
        assert least_choice_score(k, config) == choice_score(1.0, k, config) == config.map_cost * k
        assert least_trial_score(k, config) == trial_score(0.0, k, config) == config.chamfer_cost * k


def test_the_scores_are_the_documented_formulas():
    assert choice_score(0.9, 3, DEFAULT) == pytest.approx(1 - 0.9 + 0.04 * 3)
    assert trial_score(1.5, 4, DEFAULT) == pytest.approx(1.5 + 0.1 * 4)
    # a map must raise the IoU by map_cost to be worth it
    assert choice_score(0.9 + DEFAULT.map_cost, 4, DEFAULT) == pytest.approx(choice_score(0.9, 3, DEFAULT))
