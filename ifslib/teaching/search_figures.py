"""The figures of the lessons that find an IFS's maps (notebooks 07, 08 and 11): each map's copy of the target, an
attractor over its target, what each number of maps costs, and two masks over each other."""
from __future__ import annotations

from typing import Sequence

import matplotlib.pyplot as plt
import numpy as np

from .figures import EXTENT, show_image  # first: it loads ifslib.threads before torch
from ..core.geometry import patterns
from ..core.raster.chaos import chaos_game
from ..core.targets.target import Target, foreground_points

#: One colour a map for `copies_image` up to four maps: orange, blue, green, pink (more: tab10, then tab20).
COPY_COLOURS = ((1.0, 0.5, 0.05), (0.1, 0.6, 1.0), (0.2, 0.9, 0.2), (1.0, 0.2, 0.6))


def copies_image(maps, target: Target) -> np.ndarray:
    """The target in dark gray with each map's copy of it, ``T_i(A)``, tinted half way to one colour a map
    (`COPY_COLOURS`, then tab10 and tab20): a ``(size, size, 3)`` RGB image of ``(k, 2, 3)`` maps."""
    maps = np.asarray(maps, dtype=float)[:, :2, :]
    n = target.size
    image = np.zeros((n, n, 3))
    image[np.asarray(target.mask, bool)] = 0.3
    points = foreground_points(target)
    colours = COPY_COLOURS if len(maps) <= len(COPY_COLOURS) else \
        plt.get_cmap("tab10" if len(maps) <= 10 else "tab20").colors
    for i, m in enumerate(maps):
        x, y = (points @ m[:, :2].T + m[:, 2]).T
        col = np.rint((x + 0.5) * n - 0.5).astype(int)  # plane units to pixel indices
        row = np.rint((0.5 - y) * n - 0.5).astype(int)
        on = (row >= 0) & (row < n) & (col >= 0) & (col < n)
        colour = np.array(colours[i % len(colours)])
        image[row[on], col[on]] = 0.5 * image[row[on], col[on]] + 0.5 * colour
    return image


def show_copies(ax: plt.Axes, maps, target: Target, title: str | None = None) -> plt.Axes:
    """Show `copies_image` of ``maps`` ``(k, 2, 3)`` over ``target`` on the plane's extent."""
    return show_image(ax, copies_image(maps, target), title)  # RGB: show_image's cmap and limits play no part


def show_attractor(ax: plt.Axes, maps, target: Target, title: str | None = None, points: int = 20_000,
                   seed: int = 0) -> np.ndarray:
    """The target's picture with ``points`` chaos-game points of the attractor of ``maps`` ``(k, 2, 3)`` over it in
    orange; the points are returned."""
    maps = np.asarray(maps, dtype=float)[:, :2, :]
    show_image(ax, target.picture, title)
    xy = chaos_game(patterns.affine(maps, depth=1, name="shown"), points, seed=seed)
    ax.scatter(xy[:, 0], xy[:, 1], s=0.3, color="tab:orange", lw=0)
    ax.set_xlim(EXTENT[:2])
    ax.set_ylim(EXTENT[2:])
    return xy


def price_bars(ax: plt.Axes, table: Sequence[dict], map_cost: float, chosen: int | None = None) -> np.ndarray:
    """Stacked bars of what each number of maps costs: the misfit ``1 - IoU`` and the price ``map_cost * k`` of each
    row (``"maps"``, ``"iou"``) of ``table``, the ``chosen`` one outlined; returns the bars' heights."""
    ks = np.array([row["maps"] for row in table], dtype=int)
    misfit = np.array([1.0 - row["iou"] for row in table])
    price = map_cost * ks
    ax.bar(ks, misfit, color="tab:blue", label="misfit: 1 - attractor IoU")
    ax.bar(ks, price, bottom=misfit, color="tab:orange", label=f"price: {map_cost:g} per map")
    if chosen is not None and chosen in ks:
        i = int(np.nonzero(ks == chosen)[0][0])
        ax.bar([chosen], [misfit[i] + price[i]], fill=False, edgecolor="black", lw=2, label="chosen")
    ax.set_xticks(ks)
    ax.set_xlabel("number of maps k")
    ax.set_ylabel("score (lower is better)")
    ax.legend(fontsize=7)
    return misfit + price


def overlay(mask: np.ndarray, target_mask: np.ndarray) -> np.ndarray:
    """An RGB ``(n, n, 3)`` picture of two masks over each other: the target's only (blue), the other's only (orange),
    both (white)."""
    image = np.zeros(mask.shape + (3,))
    image[target_mask & ~mask] = (0.2, 0.5, 1.0)
    image[mask & ~target_mask] = (1.0, 0.5, 0.0)
    image[mask & target_mask] = 1.0
    return image
