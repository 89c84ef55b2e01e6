"""What the notebooks show: image panels, copy outlines, galleries and quiver plots, on axes in plane
coordinates, and byte-stable PNGs of them (`save_figure`)."""
from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Sequence

import matplotlib

# Headless runs must never wait on a window: without a display and outside a Jupyter kernel, draw with Agg.
if not os.environ.get("MPLBACKEND") and not os.environ.get("DISPLAY") and "ipykernel" not in sys.modules:
    matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .. import threads as _threads  # noqa: F401, E402 - before torch loads (ifslib.threads)
import torch  # noqa: E402

from ..core.geometry.ifs import IFS  # noqa: E402
from ..core.scoring.metrics import crossing_points  # noqa: E402
from ..core.raster.nearest import pixel_centres  # noqa: E402
from ..core.raster.render import figure_mask, render  # noqa: E402

EXTENT = (-0.5, 0.5, -0.5, 0.5)


def _numpy(image) -> np.ndarray:
    if isinstance(image, torch.Tensor):
        image = image.detach().cpu().numpy()
    return np.asarray(image, dtype=float)


def show_image(ax: plt.Axes, image, title: str | None = None, cmap: str = "gray") -> plt.Axes:
    """Show a ``(size, size)`` image (array or tensor) on the plane's extent, without ticks."""
    ax.imshow(_numpy(image), cmap=cmap, extent=EXTENT, vmin=0, vmax=1, interpolation="nearest")
    ax.set_xticks([])
    ax.set_yticks([])
    if title:
        ax.set_title(title, fontsize=9)
    return ax


def copy_outlines(ifs: IFS, depth: int, size: int = 256) -> np.ndarray:
    """Outlines ``(m, 5, 2)`` of the copies that make up the depth-``depth`` figure (``depth >= 1``): the bounding box of
    the depth ``depth - 1`` figure carried by each rule's map (the Hutchinson operator)."""
    return box_outlines(ifs, figure_mask(ifs, size, depth - 1))


def box_outlines(ifs: IFS, mask: np.ndarray) -> np.ndarray:
    """The bounding box of ``mask``'s pixels carried by each of ``ifs``'s maps, ``(m, 5, 2)``: on a fractal's target,
    where each map puts the whole."""
    size = mask.shape[0]
    x, y = pixel_centres(size, dtype=torch.float64)
    xs, ys = x.numpy()[mask.ravel()], y.numpy()[mask.ravel()]
    half = 0.5 / size
    x0, x1, y0, y1 = xs.min() - half, xs.max() + half, ys.min() - half, ys.max() + half
    corners = np.array([[x0, y0, 1], [x1, y0, 1], [x1, y1, 1], [x0, y1, 1], [x0, y0, 1]])
    maps = ifs.maps().detach().double().numpy()
    return np.einsum("mij,kj->mki", maps[:, :2, :], corners)


def draw_outlines(ax: plt.Axes, outlines: np.ndarray, color: str = "tab:orange") -> None:
    """Draw the ``(m, 5, 2)`` quadrilaterals from `copy_outlines`."""
    for quad in outlines:
        ax.plot(quad[:, 0], quad[:, 1], color=color, lw=1)
    ax.set_xlim(EXTENT[:2])
    ax.set_ylim(EXTENT[2:])


def draw_points(ax: plt.Axes, ifs: IFS, color: str = "tab:red", labels: bool = True) -> None:
    """Mark the control points (labelled ``p0, p1, ...``)."""
    pts = ifs.points.detach().cpu().double().numpy()
    ax.plot(pts[:, 0], pts[:, 1], "o", color=color, ms=3)
    if labels:
        for i, (x, y) in enumerate(pts):
            ax.annotate(f"p{i}", (x, y), textcoords="offset points", xytext=(3, 3), fontsize=7, color=color)


def draw_crossings(ax: plt.Axes, ifs: IFS, color: str = "red") -> int:
    """Mark where a curve crosses itself (`ifslib.metrics.crossing_points`); returns how many."""
    pts = crossing_points(ifs)
    if len(pts):
        ax.plot(pts[:, 0], pts[:, 1], "o", mfc="none", mec=color, ms=5, mew=1)
    ax.set_xlim(EXTENT[:2])
    ax.set_ylim(EXTENT[2:])
    return len(pts)


def gallery(images: Sequence[Sequence], col_titles: Sequence[str] = (), row_titles: Sequence[str] = (),
            captions: Sequence[Sequence[str]] | None = None, cell: float = 2.0) -> plt.Figure:
    """A grid of images (rows of ``(size, size)`` images), with column and row titles, captions under each image
    (e.g. its IoU) and ``cell`` inches per image."""
    rows, cols = len(images), max(len(r) for r in images)
    fig, axes = plt.subplots(rows, cols, figsize=(cell * cols, cell * rows + 0.3), squeeze=False)
    for r, row in enumerate(images):
        for c in range(cols):
            ax = axes[r, c]
            if c >= len(row):
                ax.axis("off")
                continue
            show_image(ax, row[c], col_titles[c] if r == 0 and c < len(col_titles) else None)
            if captions is not None and captions[r][c]:
                ax.set_xlabel(captions[r][c], fontsize=8)
        if r < len(row_titles):
            axes[r, 0].set_ylabel(row_titles[r], fontsize=9)
    fig.tight_layout()
    return fig


def quiver_panels(xs: np.ndarray, ys: np.ndarray, fields: Sequence[np.ndarray], titles: Sequence[str],
                  background=None, optimum=None, colors: Sequence[str] = ("tab:orange", "tab:blue", "tab:green"),
                  cell: float = 3.2) -> plt.Figure:
    """Side-by-side quiver plots of ``(ny, nx, 2)`` vector fields on the grid ``xs, ys``, each arrow scaled to unit
    length, over a faint ``background`` (the target) with the ``optimum`` starred."""
    fig, axes = plt.subplots(1, len(fields), figsize=(cell * len(fields), cell), squeeze=False)
    gx, gy = np.meshgrid(xs, ys)
    pad = 0.6 * (xs[1] - xs[0]) if len(xs) > 1 else 0.05
    for k, (ax, vec, title) in enumerate(zip(axes[0], fields, titles)):
        if background is not None:
            ax.imshow(_numpy(background), cmap="gray_r", extent=EXTENT, alpha=0.35, vmin=0, vmax=1)
        norm = np.linalg.norm(vec, axis=-1, keepdims=True)
        unit = np.divide(vec, norm, out=np.zeros_like(vec), where=norm > 0)
        ax.quiver(gx, gy, unit[..., 0], unit[..., 1], color=colors[k % len(colors)], angles="xy",
                  pivot="mid", scale_units="xy", scale=1.4 / (xs[1] - xs[0]) if len(xs) > 1 else 20, width=0.006)
        if optimum is not None:
            ax.plot(*optimum, "*", color="black", ms=10)
        ax.set_xlim(xs[0] - pad, xs[-1] + pad)
        ax.set_ylim(ys[0] - pad, ys[-1] + pad)
        ax.set_aspect("equal")
        ax.set_title(title, fontsize=9)
        ax.tick_params(labelsize=7)
    fig.tight_layout()
    return fig


def rendered(ifs: IFS, size: int, depth: int | str | None = None, **kwargs) -> np.ndarray:
    """A no-grad render as a numpy array, for showing (``depth="attractor"``, ``window``, ``method``: see `ifslib.render`)."""
    with torch.no_grad():
        return render(ifs, size, depth, **kwargs).cpu().numpy()


#: The folder `save_figure` writes to when a notebook's ``save_to`` is empty (the tests compare those figures).
FIGURES_ENV = "IFSLIB_FIGURES"


def save_figure(fig: plt.Figure, name: str, folder: str | os.PathLike | None, dpi: int = 100) -> Path | None:
    """Write ``fig`` to ``folder/name.png`` byte-stably (no software or time stamp); an empty ``folder`` uses
    ``$IFSLIB_FIGURES`` (`FIGURES_ENV`), and with neither nothing is written (None)."""
    folder = folder or os.environ.get(FIGURES_ENV)
    if not folder:
        return None
    path = Path(folder) / f"{name}.png"
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi, metadata={"Software": None})
    return path
