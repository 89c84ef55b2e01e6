"""Silhouettes the library draws itself: letters, polygons and smooth blobs, as binary masks.

They are targets that need no file: a reader's first image to fit, and the benchmark set of shapes
(`benchmarks/silhouettes.py`). Every drawing is a boolean ``(size, size)`` array in the pixel grid
of docs/guide/conventions.md (row 0 at the top), the figure centred and filling about 80% of the
frame; `ifslib.load_target` takes it as it is.
"""
from __future__ import annotations

import numpy as np
from matplotlib.font_manager import FontProperties
from matplotlib.path import Path
from matplotlib.textpath import TextPath

from ..errors import IFSError
from ..raster.distance import check_size
from ..raster.nearest import pixel_centres

#: How much of the frame the figure's larger side fills.
FILL = 0.8


def _inside(path: Path, size: int) -> np.ndarray:
    """Pixels whose centres lie inside ``path`` (plane units), as a ``(size, size)`` bool array."""
    x, y = pixel_centres(size)
    return path.contains_points(np.stack([x.numpy(), y.numpy()], 1)).reshape(size, size)


def _fitted(vertices: np.ndarray) -> np.ndarray:
    """Vertices scaled and moved so that their bounding box is centred and its larger side is `FILL`."""
    lo, hi = vertices.min(0), vertices.max(0)
    return (vertices - (lo + hi) / 2) * (FILL / max(hi - lo))


def letter(char: str, size: int = 128, font: str = "DejaVu Sans", weight: str = "bold") -> np.ndarray:
    """A letter (or any text) in a font that matplotlib ships, filled, holes kept.

    Parameters
    ----------
    char : str
        The text to draw, e.g. ``"A"``.
    size : int
        Pixels per side.
    font, weight
        Passed to `matplotlib.font_manager.FontProperties`.
    """
    size = check_size(size)
    if not isinstance(char, str) or not char.strip():
        raise IFSError(f"letter needs a non-blank string, got {char!r}")
    text = TextPath((0, 0), char, size=1, prop=FontProperties(family=font, weight=weight))
    # one polygon per contour: a point is inside when it lies in an odd number of them (holes stay holes)
    contours = text.to_polygons(closed_only=True)
    every = np.concatenate(contours)
    lo, hi = every.min(0), every.max(0)
    # one polygon per contour: a pixel is inside when it lies in an odd number of them (holes stay holes)
    inside = np.zeros((size, size), dtype=bool)
    for contour in contours:
        inside ^= _inside(Path((contour - (lo + hi) / 2) * (FILL / max(hi - lo))), size)
    return inside


def polygon(corners: int, size: int = 128, seed: int = 0, spikiness: float = 0.5) -> np.ndarray:
    """A star-shaped polygon: ``corners`` vertices at random radii and near-regular angles around the centre.

    Parameters
    ----------
    corners : int
        At least 3.
    size : int
    seed : int
    spikiness : float
        Each radius is ``1 - U(0, spikiness)`` (0: a regular polygon).
    """
    size = check_size(size)
    if isinstance(corners, bool) or not isinstance(corners, int) or corners < 3:
        raise IFSError(f"a polygon needs an integer >= 3 corners, got {corners!r}")
    rng = np.random.default_rng(seed)
    step = 2 * np.pi / corners  # corners near the regular polygon's, each moved by up to a third of a step
    angle = np.arange(corners) * step + rng.uniform(-step / 3, step / 3, corners) * (spikiness > 0)
    radius = 1 - rng.uniform(0, spikiness, corners)
    vertices = np.stack([radius * np.cos(angle), radius * np.sin(angle)], 1)
    return _inside(Path(_fitted(vertices), closed=False), size)


def blob(size: int = 128, seed: int = 0, harmonics: int = 4, roughness: float = 0.25) -> np.ndarray:
    """A smooth random blob: a closed curve ``r(theta) = 1 + sum_k a_k cos(k theta + phi_k)``.

    Parameters
    ----------
    size, seed : int
    harmonics : int
        Number of Fourier terms (2 .. ``harmonics + 1``).
    roughness : float
        Amplitude scale of the terms (each ``U(0, roughness / k)``).
    """
    size = check_size(size)
    rng = np.random.default_rng(seed)
    theta = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    r = np.ones_like(theta)
    for k in range(2, harmonics + 2):
        r += rng.uniform(0, roughness / (k - 1)) * np.cos(k * theta + rng.uniform(0, 2 * np.pi))
    vertices = np.stack([r * np.cos(theta), r * np.sin(theta)], 1)
    return _inside(Path(_fitted(vertices)), size)


def gallery(size: int = 128) -> dict[str, np.ndarray]:
    """The benchmark's silhouettes: three letters, three polygons and three blobs, by name."""
    shapes = {f"letter {c}": letter(c, size) for c in "AGR"}
    shapes.update({f"polygon {n}": polygon(n, size, seed=n) for n in (5, 7, 9)})
    shapes.update({f"blob {s}": blob(size, seed=s) for s in (1, 2, 3)})
    return shapes
