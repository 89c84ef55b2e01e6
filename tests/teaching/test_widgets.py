"""The explorer driven programmatically (the exercises' checks are in test_exercises.py)."""
import numpy as np
import pytest

import ifslib

widgets = pytest.importorskip("ifslib.teaching.widgets")


@pytest.fixture
def explorer(tmp_path, monkeypatch):
    # A self-contained "koch" target: the library's own curve saved where IFSLIB_DATA points.
    from PIL import Image

    image = ifslib.render(ifslib.patterns.koch(depth=4), 48).detach().numpy()
    Image.fromarray((image * 255).astype(np.uint8)).save(tmp_path / "koch.png")
    monkeypatch.setenv("IFSLIB_DATA", str(tmp_path))
    return widgets.Explorer("koch", depth=3, size=48)


def test_moving_a_slider_changes_the_image_and_the_maps(explorer):
    before = explorer.last
    assert before["warning"] is None and before["image"].shape == (48, 48)
    png = explorer.image.value
    explorer.sliders[2][1].value = 0.05            # lower the peak: a real slider event
    after = explorer.last
    assert not np.array_equal(after["image"], before["image"])
    assert explorer.image.value != png
    assert "T2" in explorer.info.value and "scale" in explorer.info.value
    assert np.all(after["scales"] < 1)


def test_target_shows_loss_and_iou_that_respond_to_points(explorer):
    explorer.target.value = "koch"
    at_start = dict(explorer.last)
    assert {"loss", "iou"} <= set(at_start) and "IoU" in explorer.info.value
    moved = explorer.set_point(2, 0.2, -0.3)
    assert moved["loss"] != at_start["loss"]


def test_a_curve_is_scored_by_chamfer_a_shape_by_iou(explorer):
    # as ifslib.metrics.caption: the Koch curve's fair score is its Chamfer distance, IoU is harsh on it
    explorer.target.value = "koch"
    state = explorer.last
    assert state["chamfer"] >= 0 and f"Chamfer {state['chamfer']:.2f} px" in explorer.info.value
    shifted = explorer.set_point(2, 0.2, -0.3)
    assert shifted["chamfer"] > state["chamfer"]
    explorer.pattern.value = "carpet"  # a shape with area: IoU alone
    assert "chamfer" not in explorer.last and "Chamfer" not in explorer.info.value
    assert "IoU" in explorer.info.value


def test_depth_and_sigma_change_the_render(explorer):
    ink = explorer.last["image"].sum()
    explorer.sigma.value = 4.0
    assert explorer.last["image"].sum() > ink
    explorer.depth.value = 1
    assert explorer.current().depth == 1


def test_degenerate_state_warns_instead_of_raising(explorer):
    x0, y0 = explorer.current().points[0].tolist()
    state = explorer.set_point(4, x0, y0)
    assert "zero length" in state["warning"]
    assert "zero length" in explorer.warning.value
    x, y = ifslib.patterns.koch().points[4].tolist()
    assert explorer.set_point(4, x, y)["warning"] is None
    assert explorer.warning.value == ""


def test_non_contractive_map_warns(explorer):
    state = explorer.set_point(1, 0.45, 0.45)   # segment p0 -> p1 longer than the base
    assert "contractive" in state["warning"]


def test_pattern_switch_and_json_file(explorer, tmp_path):
    explorer.pattern.value = "carpet"
    assert len(explorer.sliders) == 16 and explorer.last["warning"] is None
    path = ifslib.save_ifs(ifslib.patterns.grid(2, depth=2), tmp_path / "g.json")
    explorer.json_path.value = str(path)
    explorer.pattern.value = "JSON file"
    assert len(explorer.sliders) == 9
    explorer.json_path.value = str(tmp_path / "missing.json")
    assert "cannot load" in explorer.warning.value


def test_static_figure_of_the_state(explorer):
    fig = explorer.figure()
    assert len(fig.axes) == 1 and fig.axes[0].images
    assert fig.axes[0].get_title() == "koch, depth 3, 48²"  # a caption states its size


def test_affine_maps_in_the_explorer(explorer, tmp_path):
    from conftest import sheared

    path = ifslib.save_ifs(sheared(depth=2), tmp_path / "sheared.json")
    explorer.json_path.value = str(path)
    explorer.pattern.value = "JSON file"
    assert len(explorer.sliders) == 13 and explorer.last["warning"] is None
    before = explorer.last["image"]
    moved = explorer.set_point(5, 0.1, -0.45)       # shear the first map: its image moves
    assert moved["warning"] is None and not np.array_equal(moved["image"], before)
    p4 = explorer.current().points[4].tolist()
    flat = explorer.set_point(6, (p4[0] + 0.1) / 2, (p4[1] - 0.45) / 2)  # the first map's target points in a row
    assert "degenerate" in flat["warning"] and "degenerate" in explorer.warning.value


def test_the_explorer_draws_the_attractor_and_zooms_into_it(explorer):
    drawn = explorer.last["image"]
    explorer.attractor.value = True
    limit = explorer.last
    assert limit["attractor"] and limit["window"] is None and limit["warning"] is None
    expected = ifslib.render(explorer.current(), 48, "attractor").detach().numpy()
    np.testing.assert_allclose(limit["image"], expected, atol=1e-6)
    assert not np.array_equal(limit["image"], drawn)
    peak = explorer.current().points.detach().numpy()[2]
    explorer.zoom_x.value, explorer.zoom_y.value = float(peak[0]), float(peak[1]) - 0.004
    explorer.zoom.value = 16.0
    zoomed = explorer.last
    half = 0.5 / 16
    assert zoomed["window"] == pytest.approx((peak[0] - half, peak[1] - 0.004 - half, peak[0] + half, peak[1] - 0.004 + half))
    assert 0.02 < (zoomed["image"] >= 0.5).mean() < 0.6  # the curve crosses the window, a pixel or two wide
    assert explorer.figure() is not None


def test_the_explorer_zooms_1000x_into_the_fern(monkeypatch):
    """The zoom reaches 1024x (a window 0.001 wide): certified leaves draw it; where the certified cut
    would exceed the leaf budget, the chaos game confined to the window does."""
    explorer = widgets.Explorer("fern", size=32)
    explorer.attractor.value = True
    centre = ifslib.chaos_game(explorer.current(), 20_000, 7)[-1]
    explorer.zoom_x.value, explorer.zoom_y.value = float(centre[0]), float(centre[1])
    explorer.zoom.value = 1000.0
    zoomed = explorer.last
    assert zoomed["warning"] is None and zoomed["drawn_by"].startswith("the attractor")
    x0, y0, x1, y1 = zoomed["window"]
    assert x1 - x0 == pytest.approx(0.001) and x0 < centre[0] < x1 and y0 < centre[1] < y1
    assert 0.01 < (zoomed["image"] >= 0.5).mean() < 0.95
    assert explorer.zoom.max == widgets.MAX_ZOOM_POWER and 2.0 ** widgets.MAX_ZOOM_POWER >= 1000
    monkeypatch.setattr(ifslib.core.geometry.attractor, "DEFAULT_MAX_LEAVES", 1000)
    explorer.zoom.value = 500.0
    chaos = explorer.last
    assert chaos["warning"] is None and chaos["drawn_by"].startswith("the chaos game")
    assert 0.01 < (chaos["image"] >= 0.5).mean() < 0.95 and "chaos game" in explorer.info.value
