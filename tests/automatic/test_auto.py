"""The automatic start: curve or shape, maps that cover the figure, the skeleton's path, the ``auto``
strategy's comparison of candidates, the CLI. Every target is drawn here."""
import json

import numpy as np
import pytest
import torch
from PIL import Image

import ifslib
from ifslib.cli import main
from ifslib.automatic import auto
from ifslib.core.targets.target import target_from_mask
from ifslib.core.geometry.rules import singular_values


def ellipse_target(size=48):
    """A filled, tilted ellipse with a bump: a smooth blob."""
    r, c = np.mgrid[:size, :size]
    x, y = (c + 0.5) / size - 0.5, 0.5 - (r + 0.5) / size
    u, v = 0.8 * x + 0.6 * y, -0.6 * x + 0.8 * y
    blob = (u / 0.38) ** 2 + (v / 0.2) ** 2 <= 1
    bump = (x - 0.1) ** 2 + (y - 0.18) ** 2 <= 0.12 ** 2
    return ifslib.load_target((blob | bump).astype(float), size)


def curve_target(size=96):
    """A Koch-like curve the library draws: a thin curve with two ends."""
    return ifslib.load_target(ifslib.patterns.koch_like([[-0.4, -0.1], [-0.1, -0.05], [0.0, 0.15], [0.1, -0.05],
                                                         [0.4, -0.1]], depth=3), size)


def test_a_blob_is_a_shape_a_thin_curve_is_a_curve_and_a_network_is_a_shape():
    assert auto.classify(ellipse_target()) == "shape"
    assert auto.classify(curve_target()) == "curve"
    grid = np.zeros((64, 64))
    grid[8:56:12, 8:56] = 1
    grid[8:56, 8:56:12] = 1  # thin, but a network of lines, not one path
    assert auto.thickness(ifslib.load_target(grid, 64)) < auto.FIGURE.curve_width
    assert auto.classify(ifslib.load_target(grid, 64)) == "shape"


@pytest.mark.slow
def test_shape_start_maps_contract_and_their_copies_cover_the_figure():
    target = ellipse_target()
    for k in (3, 5):
        start = auto.shape_start(target, k, depth=2)
        assert len(start.rules) == k and all(r.kind == "affine" for r in start.rules)
        smallest, largest = singular_values(start.maps().detach())
        assert (largest <= auto.START.singular_range[1] + 1e-6).all() and (smallest >= auto.START.singular_range[0] - 1e-6).all()
        assert start.meta["pattern"] == {"name": "auto", "kind": "shape", "maps": k, "depth": 2, "primitive": "box"}
        # the collage: the start's figure already overlaps the target well
        assert ifslib.evaluate(start, target)["iou"] > 0.6
    disk = auto.shape_start(target, 4, depth=2, primitive="disk")
    assert disk.primitives[0].kind == "disk" and ifslib.evaluate(disk, target)["iou"] > 0.5


def test_skeleton_path_runs_end_to_end_and_curve_start_follows_it():
    target = curve_target()
    path = auto.skeleton_path(target)
    ends = sorted([path[0].tolist(), path[-1].tolist()])
    assert np.allclose(ends[0], [-0.4, -0.1], atol=0.03) and np.allclose(ends[1], [0.4, -0.1], atol=0.03)
    steps = np.linalg.norm(np.diff(path, axis=0), axis=1)
    assert steps.max() <= np.sqrt(2) / target.size + 1e-9  # neighbouring pixels, no jumps
    start = auto.curve_start(target, 4, depth=3)
    assert ifslib.initialization.is_curve(start) and start.meta["pattern"]["kind"] == "curve"
    # evenly spaced along the curve's own path: nearer than the paper's best-fit-line start
    line = ifslib.initialize(ifslib.patterns.koch(depth=3), target)
    assert ifslib.evaluate(start, target)["chamfer"] < min(3.0, ifslib.evaluate(line, target)["chamfer"])


def test_discover_and_its_errors():
    target = ellipse_target()
    plan = ifslib.discover(target, maps=4, depth=2)
    start = plan.start
    assert start.meta["pattern"]["maps"] == 4 and start.depth == 2 and plan.kind == "shape"
    assert plan.candidates == (start,) and plan.pattern == start.meta["pattern"]
    chosen = ifslib.discover(target)
    assert (chosen.pattern["maps"], chosen.depth) in auto.START.shape_choices and chosen.start in chosen.candidates
    assert [(len(c.rules), c.depth) for c in chosen.candidates] == list(auto.START.shape_choices)
    at_depth = ifslib.discover(target, depth=2).start
    assert at_depth.depth == 2 and at_depth.meta["pattern"]["maps"] in auto.START.shape_maps
    assert auto.choices("curve") == [(k, auto.START.default_depth) for k in auto.START.curve_maps]
    assert auto.choices("shape", maps=5) == [(5, auto.START.default_depth)]
    jittered = ifslib.discover(target, maps=4, depth=2, jitter=0.01, seed=1).start
    assert torch.equal(jittered.points[:4], start.points[:4])  # the fixed frame stays
    assert not torch.equal(jittered.points[4:], start.points[4:])
    with pytest.raises(ValueError, match="a start read from the image is ifslib.discover"):
        ifslib.initialize("auto", target)
    speck = np.zeros((32, 32), dtype=bool)
    speck[10:13, 10:13] = True
    with pytest.raises(ValueError, match="the target has 9 foreground pixels: too few for 4 maps"):
        ifslib.discover(target_from_mask(speck), maps=4)


@pytest.mark.slow
def test_auto_strategy_compares_candidates_by_loss_after_equal_steps_and_records_the_choice(tmp_path):
    target = ellipse_target(48)
    plan = ifslib.discover(target, depth=2)
    start = plan.start
    result = ifslib.fit(plan, target, steps=40, loss="multiscale_distance", progress=False)
    tried = result.history.auto.candidates
    assert [c.maps for c in tried] == list(auto.START.shape_maps) and all(c.depth == 2 and c.by == "loss" for c in tried)
    assert all(c.steps <= 40 for c in tried)
    best = min(tried, key=lambda c: (c.value, c.maps))
    assert result.history.auto.chosen == best.maps == result.best.meta["pattern"]["maps"]
    assert len(result.best.rules) == best.maps
    assert result.history.to_dict()["auto"]["candidates"] == [c.written() for c in tried]
    assert result.history.strategy == "auto" and result.history.kind == plan.kind == result.best.meta["pattern"]["kind"]
    assert result.history.cost == sum(c.steps for c in tried) + sum(s.steps for s in result.history.stages)
    last = result.history.stages[-1]
    assert last.loss == "multiscale_pixel" and last.depth == "attractor"  # a shape ends on its attractor, pixel loss
    assert ifslib.evaluate(result.best, target)["iou"] > ifslib.evaluate(start, target)["iou"]
    saved = ifslib.load_ifs(ifslib.save_ifs(result.best, tmp_path / "fit.json"))
    assert saved.meta["pattern"]["chosen"] == best.maps
    fixed = ifslib.fit(ifslib.discover(target, maps=3, depth=2), target, steps=10, progress=False)
    assert [c.maps for c in fixed.history.auto.candidates] == [3]  # a number of maps given: no comparison
    with pytest.raises(ValueError, match="strategy 'auto' fits an automatic start"):
        ifslib.fit(ifslib.patterns.koch(), target, strategy="auto", steps=2, progress=False)
    with pytest.raises(ValueError, match=r"fix the depth with ifslib.discover\(target, depth=...\)"):
        ifslib.fit(plan, target, depth=3, steps=2, progress=False)


@pytest.mark.slow
def test_cli_fits_any_image_with_pattern_auto(tmp_path, capsys):
    target = ellipse_target(48)
    png = tmp_path / "blob.png"
    Image.fromarray((target.mask * 255).astype(np.uint8)).save(png)
    out = tmp_path / "blob.json"
    assert main(["fit", str(png), "--pattern", "auto", "--size", "48", "--depth", "2", "--steps", "20", "--quiet",
                 "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "(auto: a shape, " in text and "maps chosen by the loss after" in text
    doc = json.loads(out.read_text())
    assert doc["meta"]["pattern"]["name"] == "auto" and doc["rules"][0]["kind"] == "affine"
    assert main(["fit", str(png), "--pattern", "koch", "--maps", "3", "-o", str(out)]) == 2
    assert "--maps goes with --pattern auto" in capsys.readouterr().err
    assert main(["fit", str(png), "--pattern", "koch", "--learned", "-o", str(out)]) == 2
    assert "--learned goes with --pattern auto" in capsys.readouterr().err


def test_silhouettes_are_centred_filled_and_keep_their_holes():
    from scipy import ndimage

    from ifslib.core.targets import silhouettes

    a = silhouettes.letter("A", 64)
    holes = ndimage.binary_fill_holes(a) & ~a
    assert holes.sum() > 10  # the A's counter stays a hole
    for mask in (a, silhouettes.polygon(6, 64, seed=2), silhouettes.blob(64, seed=4)):
        rows, cols = np.nonzero(mask)
        extent = max(rows.max() - rows.min(), cols.max() - cols.min()) + 1
        assert abs(extent - silhouettes.FILL * 64) <= 2
        assert abs((rows.min() + rows.max()) / 2 - 31.5) <= 1.5 and abs((cols.min() + cols.max()) / 2 - 31.5) <= 1.5
        assert auto.classify(ifslib.load_target(mask.astype(float), 64)) == "shape"
    assert len(silhouettes.gallery(32)) == 9
    with pytest.raises(ValueError, match="a polygon needs an integer >= 3 corners"):
        silhouettes.polygon(2)
    with pytest.raises(ValueError, match="letter needs a non-blank string"):
        silhouettes.letter(" ")


def test_a_dotted_thin_line_is_still_a_curve():
    """A thin anti-aliased line thresholded at mid-range breaks into dots (the paper's koch.png at 256²)."""
    mask = curve_target(96).mask.copy()
    mask[::3, :] = False
    mask[:, ::4] = False
    dotted = target_from_mask(mask)
    from scipy import ndimage

    assert ndimage.label(mask, np.ones((3, 3)))[1] > 5
    assert auto.classify(dotted) == "curve"
    start = auto.curve_start(dotted, 4)
    assert ifslib.evaluate(start, curve_target(96))["chamfer"] < 3.0


@pytest.mark.parametrize("picture, argv, message", [
    ("one", [], "the figure has 1 pixel(s): too few"),
    ("empty", [], "the target image is uniform"),
    ("full", [], "the target image is uniform"),
    ("square", ["--maps", "0"], "number of maps must be an integer >= 1, got 0"),
    ("square", ["--maps", "1000"], "number of maps must be at most 64, got 1000"),
])
def test_cli_refuses_what_no_automatic_start_can_fit(tmp_path, capsys, picture, argv, message):
    from PIL import Image

    import ifslib.cli

    image = np.zeros((32, 32), np.uint8)
    if picture == "one":
        image[10, 12] = 255
    elif picture == "full":
        image[:] = 255
    elif picture == "square":
        image[8:24, 8:24] = 255
    path = tmp_path / f"{picture}.png"
    Image.fromarray(image).save(path)
    code = ifslib.cli.main(["fit", str(path), "--pattern", "auto", "--size", "32", "--quiet", "-o",
                            str(tmp_path / "fit.json")] + argv)
    assert code == 2
    assert message in capsys.readouterr().err


def test_the_curve_path_decides_the_kind_and_is_the_path_the_curve_starts_follow():
    curve, blob = curve_target(), ellipse_target()
    path = auto.curve_path(curve)
    assert auto.curve_path(blob) is None and np.array_equal(path, auto.skeleton_path(curve))
    handed = auto.candidates(curve, [(3, 2), (4, 2)], kind="curve", path=path)
    walked = auto.candidates(curve, [(3, 2), (4, 2)], kind="curve")
    assert all(a.points.equal(b.points) for a, b in zip(handed, walked))
