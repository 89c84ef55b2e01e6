"""The partition chosen again: within its bit budget, a whole quadtree, and its error the pruning's, exactly."""
import pytest
import torch

from ifslib.compression.config import CodeOptions
from ifslib.compression.decode import iterate, plan
from ifslib.compression.encode import encode
from ifslib.compression.fileformat import from_bytes, to_bytes
from ifslib.compression.rates import choose
from ifslib.compression.repartition import level_choices, partition
from compression_images import photo


@pytest.mark.parametrize("coder", ["fixed", "adaptive"])
def test_the_new_code_keeps_the_budget_and_its_collage_error_is_the_prunings(coder):
    options = CodeOptions(min_block=4, max_block=16, coder=coder)
    image = photo(64, seed=6)
    code = encode(image, options, bpp=1.0)
    for budget in (code.bits() // 2, code.bits()):
        new = partition(image, image, 64, 64, options, budget).code  # the pool cut from the image itself: the collage
        assert new.bits() <= budget
        assert int((new.size ** 2).sum()) == 64 * 64
        back = from_bytes(to_bytes(new))
        assert torch.equal(back.size, new.size) and torch.equal(back.s_idx, new.s_idx)
        assert (new.domain[new.flat] == 0).all() and (new.iso[new.flat] == 0).all()
        chosen = choose(level_choices(image, image, options), 64, 64, options, budget)
        assert torch.equal(chosen.code.size, new.size)
        collage = iterate(plan(new), image, new.s(), new.m())
        assert float(((collage - image) ** 2).sum()) == pytest.approx(chosen.err, rel=1e-4)
