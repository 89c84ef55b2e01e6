"""The explorer: move an IFS's control points with sliders and watch the fractal, its maps and its fit (ipywidgets)."""
from __future__ import annotations

import html
import io
import time

import numpy as np

from .. import threads as _threads  # noqa: F401 - before torch loads (ifslib.threads)
import torch  # noqa: E402
from PIL import Image, ImageDraw

try:
    import ipywidgets as w
except ImportError as exc:  # pragma: no cover - depends on the environment
    raise ImportError("ifslib.widgets needs ipywidgets: pip install ipywidgets (or pip install -e '.[dev]')") from exc

from . import figures
from ..core.raster.distance import distance_field, pixel_size
from ..errors import IFSError, LeafBudgetError
from ..core.raster.chaos import chaos_field
from ..core.geometry.ifs import IFS
from ..core.geometry.io import load_ifs
from ..core.scoring.losses import loss as loss_fn
from ..core.scoring.metrics import chamfer, iou
from ..core.geometry.crossings import is_curve
from ..core.geometry.patterns import by_name
from ..core.raster.render import shade
from ..core.targets.target import Target, load_target

PATTERNS = ("koch", "koch_paper", "carpet", "grid3", "rosette6", "fern", "JSON file")

#: The deepest zoom, a power of 2: a 256² window of the fern at 1024x has about 3 million leaves.
MAX_ZOOM_POWER = 10
TARGETS = ("none", "koch", "sierpinski", "apple", "flower")


def _maps_table(ifs: IFS) -> str:
    """HTML table of each rule's map (top two rows of the 3 x 3 matrix) and contraction factor."""
    maps = ifs.maps().detach().double().numpy()
    scales = ifs.scales().double().numpy()
    rows = "".join(
        f"<tr><td>T{i + 1}</td><td>[{m[0, 0]:+.3f} {m[0, 1]:+.3f} | {m[0, 2]:+.3f}]<br>"
        f"[{m[1, 0]:+.3f} {m[1, 1]:+.3f} | {m[1, 2]:+.3f}]</td>"
        f"<td style='color:{'inherit' if s < 1 else 'red'}'>{s:.3f}</td></tr>"
        for i, (m, s) in enumerate(zip(maps, scales)))
    return ("<table style='font-family:monospace;font-size:11px'><tr><th>map</th><th>[A | t]</th>"
            f"<th>scale</th></tr>{rows}</table>")


class Explorer:
    """Sliders for an IFS's control points, depth and sigma, with a live ``size`` render of a ``pattern`` of
    `PATTERNS` (``"JSON file"`` reads ``json_path``); with a ``target`` (a paper image) its loss and IoU are shown."""

    def __init__(self, pattern: str = "koch", depth: int = 3, size: int = 256, target: str = "none",
                 json_path: str = "") -> None:
        self.size = size
        self._targets: dict[str, Target] = {}
        self.pattern = w.Dropdown(options=PATTERNS, value=pattern, description="pattern")
        self.json_path = w.Text(value=json_path, placeholder="path/to/ifs.json", description="JSON")
        self.depth = w.IntSlider(value=depth, min=0, max=7, description="depth")
        self.sigma = w.FloatSlider(value=1.0, min=0.25, max=8.0, step=0.25, description="σ (pixels)")
        self.target = w.Dropdown(options=TARGETS, value=target, description="target")
        self.show_outlines = w.Checkbox(value=True, description="copy outlines")
        self.attractor = w.Checkbox(value=False, description="attractor")
        self.zoom = w.FloatLogSlider(value=1.0, base=2, min=0, max=MAX_ZOOM_POWER, step=0.5, description="zoom")
        # a 1024x window is 0.001 wide: its centre moves by a hundredth of it
        self.zoom_x = w.FloatSlider(value=0.0, min=-0.5, max=0.5, step=1e-5, readout_format=".5f", description="zoom x")
        self.zoom_y = w.FloatSlider(value=0.0, min=-0.5, max=0.5, step=1e-5, readout_format=".5f", description="zoom y")
        self.image = w.Image(format="png", width=size, height=size)
        self.info = w.HTML()
        self.warning = w.HTML()
        self.points = w.VBox()
        self.sliders: list[tuple[w.FloatSlider, w.FloatSlider]] = []
        self.last: dict = {}
        self._quiet = False
        self.ifs = self._load_pattern()
        self._build_sliders()
        for control in (self.depth, self.sigma, self.target, self.show_outlines, self.attractor, self.zoom, self.zoom_x,
                        self.zoom_y):
            control.observe(self.update, names="value")
        self.pattern.observe(self._pattern_changed, names="value")
        self.json_path.observe(self._pattern_changed, names="value")
        self.update()

    # -- state -------------------------------------------------------------------------------------
    def _load_pattern(self) -> IFS:
        if self.pattern.value == "JSON file":
            return load_ifs(self.json_path.value) if self.json_path.value else by_name("koch")
        return by_name(self.pattern.value)

    def _pattern_changed(self, _change=None) -> None:
        try:
            self.ifs = self._load_pattern()
        except (IFSError, OSError) as exc:
            self._warn(f"cannot load the pattern: {exc}")
            return
        self._build_sliders()
        self.update()

    def _build_sliders(self) -> None:
        self._quiet = True
        self.sliders = []
        rows = []
        for i, (x, y) in enumerate(self.ifs.points.detach().double().numpy()):
            pair = tuple(w.FloatSlider(value=float(v), min=-0.6, max=0.6, step=0.001, readout_format=".3f",
                                       continuous_update=False, description=f"p{i}.{axis}",
                                       layout=w.Layout(width="260px"))
                         for v, axis in ((x, "x"), (y, "y")))
            for s in pair:
                s.observe(self.update, names="value")
            self.sliders.append(pair)
            rows.append(w.HBox(list(pair)))
        self.points.children = rows
        self._quiet = False

    def current(self) -> IFS:
        """The IFS the sliders describe (a fresh copy)."""
        pts = torch.tensor([[sx.value, sy.value] for sx, sy in self.sliders], dtype=self.ifs.points.dtype)
        ifs = self.ifs.clone(pts)
        ifs.depth = self.depth.value
        return ifs

    def set_point(self, index: int, x: float, y: float) -> dict:
        """Move control point ``index`` to ``(x, y)`` and redraw once (for scripts and tests)."""
        self._quiet = True
        self.sliders[index][0].value, self.sliders[index][1].value = x, y
        self._quiet = False
        return self.update()

    def _target(self) -> Target | None:
        name = self.target.value
        if name == "none":
            return None
        if name not in self._targets:
            self._targets[name] = load_target(name, self.size)
        return self._targets[name]

    def window(self) -> tuple[float, float, float, float] | None:
        """The box of the plane drawn: None for the frame, else ``zoom``'s square around (``zoom x``, ``zoom y``)."""
        if self.zoom.value <= 1:
            return None
        half = 0.5 / self.zoom.value
        return (self.zoom_x.value - half, self.zoom_y.value - half, self.zoom_x.value + half, self.zoom_y.value + half)

    # -- drawing -----------------------------------------------------------------------------------
    def _warn(self, message: str) -> None:
        self.warning.value = (f"<div style='background:#fff3cd;color:#664d03;padding:4px'>⚠ "
                              f"{html.escape(message)}</div>")
        self.last = {"warning": message}

    def _png(self, image: np.ndarray, outlines: np.ndarray | None) -> bytes:
        pil = Image.fromarray((np.clip(image, 0, 1) * 255).astype(np.uint8)).convert("RGB")
        if outlines is not None:
            draw = ImageDraw.Draw(pil)
            for quad in outlines:
                pix = [((x + 0.5) * self.size - 0.5, (0.5 - y) * self.size - 0.5) for x, y in quad]
                draw.line(pix, fill=(255, 140, 0), width=1)
        buf = io.BytesIO()
        pil.save(buf, format="png")
        return buf.getvalue()

    def update(self, _change=None) -> dict:
        """Redraw from the controls; returns what was drawn (the image, scales, the scores against a target), or only the
        ``warning`` of an invalid state."""
        if self._quiet:
            return self.last
        started = time.perf_counter()
        ifs = self.current()
        window = self.window()
        limit = self.attractor.value or window is not None  # the attractor itself, possibly zoomed
        try:
            with torch.no_grad():
                drawn_by = "the attractor's certified leaves" if limit else f"depth {ifs.depth}"
                if limit:
                    try:
                        dist = distance_field(ifs, self.size, "attractor", window=window)
                    except LeafBudgetError:  # overlapping copies: the cut outgrows the budget, the chaos game does not
                        dist = chaos_field(ifs, self.size, window=window).float()
                        drawn_by = "the chaos game (the certified cut needs more leaves than the budget)"
                else:
                    dist = distance_field(ifs, self.size)
                image = shade(dist, self.sigma.value * pixel_size(self.size, window)).numpy()
                outlines = (figures.copy_outlines(ifs, ifs.depth, self.size)
                            if self.show_outlines.value and ifs.depth > 0 and window is None else None)
                target = None if window is not None else self._target()
                state = {"image": image, "scales": ifs.scales().numpy(), "warning": None, "window": window,
                         "attractor": limit, "drawn_by": drawn_by}
                text = _maps_table(ifs)
                if target is not None:
                    state["loss"] = float(loss_fn(dist, target, "multiscale_distance"))
                    state["iou"] = iou(image >= 0.5, target.mask)
                    score = f"IoU {state['iou']:.3f}"
                    if is_curve(ifs):  # the measure metrics.caption picks for a curve
                        state["chamfer"] = chamfer(image >= 0.5, target.mask)
                        score = f"Chamfer {state['chamfer']:.2f} px ({score}, harsh on a thin curve)"
                    text += f"<p>multiscale distance loss {state['loss']:.3e}, {score}</p>"
        except IFSError as exc:
            self._warn(str(exc))
            return self.last
        self.image.value = self._png(image, outlines)
        state["seconds"] = time.perf_counter() - started
        note = f" from {html.escape(drawn_by)}" if drawn_by.startswith("the chaos") else ""
        self.info.value = text + f"<p style='color:gray'>redrawn in {1000 * state['seconds']:.0f} ms{note}</p>"
        self.warning.value = ""
        self.last = state
        return state

    def figure(self):
        """The current state as a static matplotlib figure (what a headless run shows)."""
        import matplotlib.pyplot as plt

        ifs = self.current()
        fig, ax = plt.subplots(figsize=(4, 4))
        if self.last.get("image") is not None:
            what = "the attractor" if self.last.get("attractor") else f"depth {ifs.depth}"
            figures.show_image(ax, self.last["image"], f"{self.pattern.value}, {what}, {self.size}²")
            if self.last.get("window") is not None:
                return fig  # a zoomed window: the outlines and points are of the whole frame
            if self.show_outlines.value and ifs.depth > 0:
                figures.draw_outlines(ax, figures.copy_outlines(ifs, ifs.depth, self.size))
            figures.draw_points(ax, ifs)
        else:
            ax.text(0.5, 0.5, self.last.get("warning", ""), ha="center", va="center", wrap=True)
            ax.set_axis_off()
        return fig

    @property
    def widget(self) -> w.Widget:
        """The whole explorer as one widget."""
        controls = w.VBox([self.pattern, self.json_path, self.depth, self.sigma, self.target, self.show_outlines,
                           self.attractor, self.zoom, self.zoom_x, self.zoom_y])
        return w.VBox([w.HBox([controls, self.image]), self.warning, w.HBox([self.points, self.info])])

    def _ipython_display_(self) -> None:
        from IPython.display import display

        display(self.widget)
