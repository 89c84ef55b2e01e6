"""The domain pool against slicing by hand, and the 8 isometries as the square's symmetry group."""
import torch

from ifslib.compression.config import MAX_DOMAINS
from ifslib.compression.domains import (ISOMETRIES, domain_bits, domain_count, domain_step, isometry, lattice, pool,
                                        pool_with_isometries)
from compression_images import photo


def test_the_eight_isometries_are_distinct_and_preserve_pixels():
    block = torch.arange(16.0).reshape(4, 4)
    images = [isometry(block, k) for k in range(ISOMETRIES)]
    assert len({tuple(i.reshape(-1).tolist()) for i in images}) == 8
    for image in images:
        assert sorted(image.reshape(-1).tolist()) == block.reshape(-1).tolist()
    assert torch.equal(images[0], block)
    assert torch.equal(images[4], block.T)


def test_pool_is_each_lattice_block_averaged_by_hand():
    image = photo(32)
    for size in (4, 8):
        step = domain_step(32, 32, size)
        rows, cols = lattice(32, 32, size)
        blocks = pool(image, size)
        assert blocks.shape == (rows * cols, size, size)
        for d in (0, cols - 1, len(blocks) - 1):
            y, x = (d // cols) * step, (d % cols) * step
            big = image[y:y + 2 * size, x:x + 2 * size]
            by_hand = big.reshape(size, 2, size, 2).mean((1, 3))
            torch.testing.assert_close(blocks[d], by_hand)


def test_pool_with_isometries_orders_isometry_first():
    image = photo(32)
    every = pool_with_isometries(image, 4)
    blocks = pool(image, 4)
    assert every.shape == (8, len(blocks), 16)
    torch.testing.assert_close(every[5, 3], isometry(blocks[3], 5).reshape(-1))


def test_the_lattice_is_capped_and_its_index_fits_its_bits():
    assert domain_step(32, 32, 4) == 4 and lattice(32, 32, 4) == (7, 7)
    for side in (64, 256, 512, 1024):
        for size in (4, 8, 16):
            count = domain_count(side, side, size)
            assert 0 < count <= MAX_DOMAINS
            assert 2 ** domain_bits(side, side, size) >= count
    assert domain_step(256, 256, 4) == 8  # 3969 positions at step 4: doubled
