"""`animate`: a fit's progress as a GIF (or MP4 with ffmpeg), beside the target and the difference.

Each frame shows, left to right: the target, the fractal at a kept step, and their difference
(red where the fractal draws too much, blue where it misses the target), as the paper's
repository shows in its README. The frames come from ``fit(..., options=RunOptions(keep_every=N))``.
"""
from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import numpy as np

from .. import threads as _threads  # noqa: F401 - before torch loads (ifslib.threads)
import torch  # noqa: E402
from PIL import Image, ImageDraw
from tqdm.auto import tqdm

from ..errors import IFSError
from ..core.geometry.io import ifs_from_dict
from ..core.raster.render import render
from ..core.targets.target import Target
from ..core.fitting.result import History

GAP = 4  # pixels between the three panels


def frame(image: np.ndarray, target: np.ndarray, label: str = "") -> np.ndarray:
    """One ``(size, 3 * size + 2 * GAP, 3)`` uint8 frame: target | image | difference."""
    size = target.shape[0]
    gray = lambda a: np.repeat((np.clip(a, 0, 1) * 255).astype(np.uint8)[..., None], 3, -1)  # noqa: E731
    diff = np.clip(image, 0, 1) - target
    rgb = np.zeros((size, size, 3), np.uint8)
    rgb[..., 0] = (np.clip(diff, 0, 1) * 255).astype(np.uint8)
    rgb[..., 2] = (np.clip(-diff, 0, 1) * 255).astype(np.uint8)
    gap = np.full((size, GAP, 3), 64, np.uint8)
    out = np.concatenate([gray(target), gap, gray(image), gap, rgb], 1)
    if label:
        pil = Image.fromarray(out)
        ImageDraw.Draw(pil).text((size + GAP + 2, 1), label, fill=(255, 200, 0))
        out = np.asarray(pil)
    return out


def animate(history: History | dict, target: Target, path: str | os.PathLike, fps: int = 10, progress: bool = True) -> Path:
    """Write a fit's progress as an animation.

    Parameters
    ----------
    history : History or dict
        ``FitResult.history`` of a fit run with ``keep_every`` (it holds the pattern and the kept
        points), or a saved fit's ``meta["history"]``.
    target : Target
        The fit's target; frames are rendered at its size.
    path : path
        ``.gif`` (Pillow) or ``.mp4`` (needs ``ffmpeg`` on the PATH).
    fps : int
        Frames per second.
    progress : bool
        Show a progress bar over the frames.

    Returns
    -------
    pathlib.Path
    """
    if isinstance(history, dict):
        history = History.from_dict(history)
    if history.snapshots is None or history.pattern is None:
        raise IFSError("this history holds no snapshots: run fit(..., options=ifslib.RunOptions(keep_every=N)) to keep them")
    path = Path(path)
    if path.suffix.lower() not in (".gif", ".mp4"):
        raise IFSError(f"animate writes .gif or .mp4 files, got {path.name!r}")
    if not (isinstance(fps, int) and fps > 0):
        raise IFSError(f"fps must be a positive integer, got {fps!r}")
    pattern = ifs_from_dict(history.pattern)
    truth = target.image.cpu().numpy().astype(float)
    frames = []
    snaps = history.snapshots
    for step, points in tqdm(list(zip(snaps["step"], snaps["points"])), desc="frames", disable=not progress):
        with torch.no_grad():
            image = render(pattern.clone(torch.tensor(points, dtype=pattern.points.dtype)), target.size).numpy()
        frames.append(frame(image, truth, f"step {step}"))
    if not frames:
        raise IFSError("this history holds no snapshots to animate")
    path.parent.mkdir(parents=True, exist_ok=True)
    if path.suffix.lower() == ".gif":
        images = [Image.fromarray(f) for f in frames]
        images[0].save(path, save_all=True, append_images=images[1:], duration=round(1000 / fps), loop=0)
        return path
    ffmpeg = shutil.which("ffmpeg")
    if ffmpeg is None:
        raise IFSError("writing an MP4 needs ffmpeg on the PATH; write a .gif instead")
    h, w = frames[0].shape[:2]
    h2, w2 = h + h % 2, w + w % 2  # the H.264 encoder wants even sizes
    cmd = [ffmpeg, "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", f"{w2}x{h2}",
           "-r", str(fps), "-i", "-", "-pix_fmt", "yuv420p", str(path)]
    raw = b"".join(np.pad(f, ((0, h2 - h), (0, w2 - w), (0, 0))).tobytes() for f in frames)
    subprocess.run(cmd, input=raw, check=True)
    return path
