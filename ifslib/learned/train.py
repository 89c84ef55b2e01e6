"""Train the learned guess: ``python -m ifslib.learned.train`` (seeded; a progress bar and a learning curve).

Pairs are drawn by `pairs.pair` from their own seed streams (never the benchmarks' integer seeds) and seen through
one of the frame's 8 symmetries at random; the weights go to the package (`guess.WEIGHTS`) unless ``--out`` says.
"""
from __future__ import annotations

import argparse
import math
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch
from tqdm.auto import tqdm

from ..core.scoring.metrics import iou
from ..errors import IFSError, check_int
from ..threads import configure_threads
from . import config
from .estimator import WEIGHTS, clamped
from .network import GuessNet
from .pairs import SYMMETRIES, chaos_points, pair, picture, turned
from .set_loss import set_loss


@dataclass(frozen=True)
class Training:
    """What a training run does (defaults: `config`)."""

    steps: int = config.TRAIN_STEPS
    pool: int = config.POOL
    validation: int = config.VALIDATION
    batch: int = config.BATCH
    lr: float = config.LR
    width: int = config.WIDTH
    seed: int = 0
    curve_every: int = 500
    progress: bool = True

    def __post_init__(self) -> None:
        for name in ("steps", "pool", "validation", "batch", "width", "curve_every"):
            check_int(getattr(self, name), name, 1)
        check_int(self.seed, "seed", 0)
        if isinstance(self.lr, bool) or not isinstance(self.lr, (int, float)) or not 0 < self.lr < 1:
            raise IFSError(f"lr must be a learning rate in (0, 1), got {self.lr!r}")
        if not isinstance(self.progress, bool):
            raise IFSError(f"progress must be True or False, got {self.progress!r}")


def _pairs(tag: int, count: int, progress: bool) -> tuple[np.ndarray, list[np.ndarray]]:
    """``count`` pairs of stream ``tag``, drawn on every core."""
    with ProcessPoolExecutor() as pool:
        drawn = list(tqdm(pool.map(pair, [tag] * count, range(count), chunksize=256), total=count,
                          desc=f"pairs {tag}", disable=not progress))
    return np.stack([p for p, _ in drawn]), [m for _, m in drawn]


def _batch(pictures, maps, picks, rng) -> tuple[torch.Tensor, list[torch.Tensor]]:
    """The picked pairs, each seen through a random symmetry of the frame."""
    seen = [turned(pictures[i], maps[i], SYMMETRIES[rng.integers(8)]) for i in picks]
    images = torch.from_numpy(np.stack([p for p, _ in seen]).astype(np.float32))[:, None]
    return images, [torch.from_numpy(m).float() for _, m in seen]


def _validation(network: GuessNet, pictures, maps, drawn: int = 128) -> tuple[float, float]:
    """The held-out pairs' matched maps' weighted L1 (`set_loss` without its presence term, plane units), and the
    median IoU of the first ``drawn`` pairs' pictures against the attractors of their guesses given the true number
    of maps (drawn as the pairs are): the score a fit starts from."""
    network.eval()
    with torch.no_grad():
        device = network.anchors.device
        guessed, logits = network(torch.from_numpy(pictures.astype(np.float32))[:, None].to(device))
        error = set_loss(guessed, logits, [torch.from_numpy(m).float().to(device) for m in maps], 0.0,
                         network.anchors).item()
    network.train()
    rng = np.random.default_rng(0)
    ious = []
    for shown, true, slots, scores in zip(pictures[:drawn], maps, guessed.double().cpu().numpy(),
                                             logits.cpu().numpy()):
        drawn_maps = clamped(slots[np.argsort(-scores)[:len(true)]])
        mine = picture(chaos_points(drawn_maps, rng), pictures.shape[-1])
        ious.append(iou(mine, shown))
    return error, float(np.median(ious))


def train(options: Training = Training()) -> tuple[GuessNet, list[tuple[int, float, float, float]]]:
    """A network trained as ``options`` say, and its learning curve: ``(step, training loss, held-out maps' error,
    held-out attractors' median IoU)``."""
    torch.manual_seed(options.seed)
    rng = np.random.default_rng(options.seed)
    pictures, maps = _pairs(config.TRAIN_TAG, options.pool, options.progress)
    held_pictures, held_maps = _pairs(config.VALIDATION_TAG, options.validation, options.progress)
    device = "cuda" if torch.cuda.is_available() else "cpu"   # the pairs and the matching stay on the CPU
    network = GuessNet(width=options.width).to(device)
    adam = torch.optim.Adam(network.parameters(), lr=options.lr)
    schedule = torch.optim.lr_scheduler.LambdaLR(adam, lambda s: 0.5 * (1 + math.cos(math.pi * s / options.steps)))
    curve, running = [], []
    bar = tqdm(range(1, options.steps + 1), desc="train guess", disable=not options.progress)
    for step in bar:
        images, truths = _batch(pictures, maps, rng.integers(0, options.pool, options.batch), rng)
        loss = set_loss(*network(images.to(device)), [t.to(device) for t in truths], anchors=network.anchors)
        adam.zero_grad()
        loss.backward()
        adam.step()
        schedule.step()
        running.append(loss.item())
        if step % options.curve_every == 0 or step == options.steps:
            curve.append((step, float(np.mean(running)), *_validation(network, held_pictures, held_maps)))
            running = []
            bar.set_postfix(loss=f"{curve[-1][1]:.4f}", held_out=f"{curve[-1][2]:.4f}", iou=f"{curve[-1][3]:.3f}")
    return network.cpu().eval(), curve


def save(network: GuessNet, path: Path) -> None:
    """The weights as float16 (half the bytes; the guess is no finer than that) and the network's shape."""
    state = {k: v.half() for k, v in network.state_dict().items()}
    state["shape"] = {"size": network.size, "grid": network.grid, "width": network.out.in_channels // 2}
    torch.save(state, path)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=config.TRAIN_STEPS)
    parser.add_argument("--pool", type=int, default=config.POOL)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--threads", default=None, help="torch's threads (default: $IFSLIB_THREADS, else the free cores)")
    parser.add_argument("--out", type=Path, default=Path(__file__).with_name(WEIGHTS))
    args = parser.parse_args(argv)
    print(f"training on {configure_threads(args.threads)} thread(s)")
    try:
        options = Training(steps=args.steps, pool=args.pool, seed=args.seed)
    except IFSError as error:
        parser.error(str(error))
    t0 = time.perf_counter()
    network, curve = train(options)
    save(network, args.out)
    print(f"{'step':>7} {'training loss':>13} {'held-out maps error':>19} {'held-out IoU':>12}")
    for step, loss, held, iou in curve:
        print(f"{step:>7} {loss:>13.4f} {held:>19.4f} {iou:>12.3f}")
    print(f"wrote {args.out} ({args.out.stat().st_size / 1e6:.1f} MB) in {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
