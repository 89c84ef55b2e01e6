"""Small gray test images for the compression tests."""
import numpy as np
import torch


def photo(size: int = 32, seed: int = 0) -> torch.Tensor:
    """A smooth gradient with a bright disk, an edge and noise: ``(size, size)`` float32 in [0, 1]."""
    g = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:size, 0:size] / size
    image = 0.3 + 0.3 * xx + 0.2 * np.sin(6 * yy)
    image += 0.3 * (((xx - 0.6) ** 2 + (yy - 0.4) ** 2) < 0.05)
    image += 0.03 * g.standard_normal((size, size))
    return torch.as_tensor(np.clip(image, 0, 1), dtype=torch.float32)
