"""`ifslib.automatic.fractal.covers`: the sets of copies with the least collage distance, against brute force."""
from dataclasses import replace

import numpy as np
import torch

from ifslib.automatic import fractal
from ifslib.core.targets.target import foreground_points
from common_testing import fractal_target


def test_collage_sets_find_the_least_collage_set_of_a_small_pool_as_brute_force_does():
    """Greedy plus swaps against every set of a small pool: the set with the least collage distance is found,
    and it is the true maps hidden among perturbed copies of them."""
    from itertools import combinations

    truth, target = fractal_target(maps=3, seed=1, size=64)
    true_maps = truth.maps().detach().double()[:, :2].numpy()
    rng = np.random.default_rng(0)
    pool = [true_maps[i % 3] + rng.normal(0, 0.04, (2, 3)) * (i >= 3) for i in range(18)]  # 0-2: the truth
    pool = np.array(pool)
    every_pixel = replace(fractal.DEFAULT, restarts=6, collage_points=(64 * 64, 2000))
    sets = fractal.collage_sets(pool, target, [2, 3], config=every_pixel)

    fg = foreground_points(target)
    for k in (2, 3):
        combos = np.array(list(combinations(range(len(pool)), k)))
        outside, cover = fractal.collage_terms(torch.as_tensor(pool[combos], dtype=torch.float32),
                                               torch.as_tensor(fg, dtype=torch.float32), target.distance.float())
        brute = combos[int(torch.argmin(outside + cover))]
        assert sets[k][0] == sorted(brute.tolist())
        assert len({tuple(s) for s in sets[k]}) == len(sets[k])  # distinct
    assert sets[3][0] == [0, 1, 2]
