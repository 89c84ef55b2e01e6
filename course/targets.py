"""The exercises' fit targets, drawn from truths that only the instructor's source holds.

``python course/targets.py`` renders the attractor of each truth at the sizes a notebook may ask
for and writes its mask as a 1-bit PNG into ``ifslib/teaching/exercises/targets/``: the installed
package ships the pictures a student fits, never the maps that drew them. The hidden tests of the
notebooks (tutorial exercise 10, 05 and 07) hold the same truths.
"""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
from PIL import Image

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import ifslib  # noqa: E402
from ifslib.teaching.exercises.targets import FOLDER, SIZES  # noqa: E402


def koch_truth() -> ifslib.IFS:
    """A Koch-like curve the library does not ship: its five points drawn at random (seed 6000), turned."""
    rng = np.random.default_rng(6000)
    knee = rng.uniform(0.3, 0.36)
    peak = [rng.uniform(0.45, 0.55), rng.uniform(0.22, 0.3)]
    shape = np.array([[0, 0], [knee, 0], peak, [1 - rng.uniform(0.3, 0.36), 0], [1, 0]])
    pts = (shape - [0.5, (shape[:, 1].max() + shape[:, 1].min()) / 2]) * 0.8
    turn = math.radians(rng.choice([-1, 1]) * rng.uniform(20, 40))
    c, s = math.cos(turn), math.sin(turn)
    return ifslib.patterns.koch_like(pts @ np.array([[c, s], [-s, c]]), depth=3, name="koch_exercise")


def carpet_truth() -> ifslib.IFS:
    """A Sierpinski carpet of other proportions: a rectangle, its corner cells narrower than a third."""
    rng = np.random.default_rng(9000)
    width, height = 0.8, float(rng.uniform(0.55, 0.65))
    fx, fy = rng.uniform(0.2, 0.26, 2)
    xs = np.array([0, fx, 1 - fx, 1]) * width - width / 2
    ys = np.array([0, fy, 1 - fy, 1]) * height - height / 2
    maps = []
    for j in range(3):
        for i in range(3):
            if (i, j) != (1, 1):
                a, b = (xs[i + 1] - xs[i]) / width, (ys[j + 1] - ys[j]) / height
                maps.append([[a, 0, (xs[i] + xs[i + 1]) / 2], [0, b, (ys[j] + ys[j + 1]) / 2]])
    return ifslib.patterns.affine(maps, depth=3, name="carpet_exercise")


def two_map_truth() -> ifslib.IFS:
    """Two similarities of scale 0.42-0.5 turned by up to 0.6 rad, far enough apart that their copies do not touch."""
    rng = np.random.default_rng(10_000)
    maps = np.zeros((2, 2, 3))
    for i, centre in enumerate(([-0.25, -0.12], [0.25, 0.12])):
        a = rng.uniform(-0.6, 0.6)
        rot = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
        maps[i, :, :2] = rot * rng.uniform(0.42, 0.5)
        maps[i, :, 2] = centre
    return ifslib.patterns.affine(maps, depth=6, name="two_map_exercise")


TRUTHS = {"koch": koch_truth, "carpet": carpet_truth, "two_maps": two_map_truth}


def mask(name: str, size: int) -> np.ndarray:
    """``(size, size)`` bool: the truth's attractor as a target's figure."""
    return ifslib.load_target(TRUTHS[name](), size, depth="attractor").mask.astype(bool)


def main() -> None:
    FOLDER.mkdir(parents=True, exist_ok=True)
    for name in TRUTHS:
        for size in SIZES:
            Image.fromarray(mask(name, size)).save(FOLDER / f"{name}_{size}.png", optimize=True)
            print(f"wrote {name}_{size}.png")


if __name__ == "__main__":
    main()
