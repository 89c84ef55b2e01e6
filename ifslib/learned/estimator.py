"""A first guess of an IFS's maps from its picture, by the trained network shipped with the package."""
from __future__ import annotations

import functools
from importlib import resources

import numpy as np
import torch
import torch.nn.functional as F

from ..core.geometry import patterns
from ..core.geometry.patterns import conjugated
from ..core.geometry.ifs import IFS
from ..core.targets.target import Target
from ..errors import IFSError, check_int
from . import config
from .network import GuessNet

#: The weights `python -m ifslib.learned.train` writes, shipped as package data.
WEIGHTS = "guess.pt"
#: A guessed map's singular values are clamped below this: the fits need contractive maps.
MAX_SCALE = 0.95


@functools.lru_cache(maxsize=1)
def load_network() -> GuessNet:
    """The shipped network, in evaluation mode (loaded once: `torch.load` with ``weights_only=True``)."""
    path = resources.files(__package__) / WEIGHTS
    if not path.is_file():
        raise IFSError(f"the learned guess's weights are missing ({path}); train them with "
                       "`python -m ifslib.learned.train`")
    with resources.as_file(path) as file:
        state = torch.load(file, weights_only=True, map_location="cpu")
    network = GuessNet(**state.pop("shape"))
    network.load_state_dict({k: v.float() for k, v in state.items()})
    return network.eval()


def framing(mask: np.ndarray, extent: float = config.EXTENT) -> tuple[float, np.ndarray]:
    """``k, b`` of the similarity ``S(x) = k x + b`` that puts the figure's box at the frame's centre, its longer
    side ``extent``: the framing of the training pairs."""
    size = mask.shape[0]
    rows, cols = np.nonzero(mask)
    lo = np.array([cols.min() / size - 0.5, 0.5 - (rows.max() + 1) / size])
    hi = np.array([(cols.max() + 1) / size - 0.5, 0.5 - rows.min() / size])
    k = extent / float((hi - lo).max())
    return k, -k * (lo + hi) / 2


def reframed(mask: np.ndarray, k: float, b: np.ndarray, size: int = config.SIZE) -> torch.Tensor:
    """``(size, size)`` float: the figure moved by ``S`` and max-pooled to the network's picture."""
    fine = 4 * size
    t = (np.arange(fine) + 0.5) / fine
    x, y = np.meshgrid(t - 0.5, 0.5 - t)
    sx, sy = (x - b[0]) / k, (y - b[1]) / k       # the source point S^-1(p) of each fine pixel
    n = mask.shape[0]
    col, row = np.floor((sx + 0.5) * n).astype(int), np.floor((0.5 - sy) * n).astype(int)
    inside = (col >= 0) & (col < n) & (row >= 0) & (row < n)
    moved = np.zeros((fine, fine), dtype=np.float32)
    moved[inside] = mask[row[inside], col[inside]]
    return F.max_pool2d(torch.from_numpy(moved)[None, None], 4)[0, 0]


def clamped(maps: np.ndarray, top: float = MAX_SCALE) -> np.ndarray:
    """The maps with their linear parts' singular values clamped to ``top``: contractive, as every fit needs."""
    u, s, vt = np.linalg.svd(maps[:, :, :2])
    linear = u @ (np.minimum(s, top)[:, :, None] * vt)
    return np.concatenate([linear, maps[:, :, 2:]], 2)


def guess_maps(mask: np.ndarray, network: GuessNet | None = None, maps: int | None = None) -> np.ndarray:
    """``(k, 2, 3)`` maps whose attractor the network reads in the figure ``mask``: the ``maps`` slots most surely
    present, or as many as the presence scores expect (`expected_maps`)."""
    network = network or load_network()
    k, b = framing(mask)
    with torch.no_grad():
        guessed, logits = network(reframed(mask, k, b, network.size)[None, None])
    guessed, logits = guessed[0].double().numpy(), logits[0].double().numpy()
    count = expected_maps(logits) if maps is None else maps
    keep = np.argsort(-logits)[:count]
    return conjugated(clamped(guessed[keep]), 1 / k, -b / k)   # back by S^-1(x) = (x - b) / k


def expected_maps(logits: np.ndarray) -> int:
    """The number of maps the presence scores expect, 2 to `config.MAX_MAPS`: the sum of the slots' chances of
    holding a map. Training weighted a present slot `config.PRESENT_WEIGHT` times, so a score's odds are that many
    times a chance's."""
    odds = np.exp(np.minimum(logits, 50.0)) / config.PRESENT_WEIGHT
    return int(np.clip(np.round((odds / (1 + odds)).sum()), 2, config.MAX_MAPS))


def guess(target, maps: int | None = None, depth: int = 3) -> IFS:
    """The learned first guess of the IFS whose attractor ``target`` shows.

    Parameters
    ----------
    target : Target or array-like
        The figure: a `Target` or a square boolean mask, row 0 at the top.
    maps : int, optional
        The number of maps, 2 to 10; by default as many as the network expects (`expected_maps`).
    depth : int
        The returned IFS's drawing depth.

    Returns
    -------
    IFS
        Affine rules (`patterns.affine`), one per map the network found present, for a fit to refine.
    """
    mask = target.mask if isinstance(target, Target) else np.asarray(target)
    if mask.ndim != 2 or mask.shape[0] != mask.shape[1] or not mask.any():
        raise IFSError(f"the learned guess reads a square mask with a figure in it, got shape {mask.shape}")
    if maps is not None:
        check_int(maps, "maps", 2, maximum=config.MAX_MAPS)
    return patterns.affine(guess_maps(mask.astype(bool), maps=maps), depth=depth, name="learned guess")
