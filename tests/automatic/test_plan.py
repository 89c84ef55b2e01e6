"""The plan: which figures are searched as fractals (porous, or solid with a rough edge), which are fitted both as
a fractal and as a shape (`ambiguous`), and the silhouettes with thin parts that make a solid figure look porous."""
import numpy as np
import pytest

import ifslib
from ifslib.automatic import auto, fractal, plan
from ifslib.automatic.config import AUTO
from ifslib.core.targets import silhouettes
from ifslib.automatic import fit_plan as automatic
from ifslib.core.targets.target import target_from_mask
from common_testing import benchmark_module, fractal_target

literature_ifs = benchmark_module("samplers").literature_ifs


@pytest.fixture(scope="module")
def overlap():
    """Three overlapping copies whose attractor is a solid figure with a fractal edge, at 128²."""
    truth = literature_ifs("overlap", 3, 0, extent=0.75)
    return target_from_mask(ifslib.render(truth, 128, method="chaos", points=300_000, seed=0).numpy() >= 0.5)


@pytest.fixture
def searches(monkeypatch):
    """The fractal search stood in for by one that finds nothing: the list of ``(target, config)`` it was asked for."""
    calls = []

    def no_fractal(target, maps, depth, seed, *, config, learned=False):
        calls.append((target, config))
        return None, {"search": [], "rule": "", "verdict": "none"}, None

    monkeypatch.setattr(plan, "fractal_start", no_fractal)
    return calls


def _koch_snowflake(size: int) -> np.ndarray:
    """The filled Koch snowflake (five levels) drawn at ``size``²: a solid figure whose edge has dimension 1.26."""
    from matplotlib.path import Path

    turn = np.array([[0.5, -np.sqrt(3) / 2], [np.sqrt(3) / 2, 0.5]])
    corners = [0.45 * np.array([np.cos(a), np.sin(a)]) for a in np.pi / 2 - np.arange(3) * 2 * np.pi / 3]
    points = corners + [corners[0]]
    for _ in range(5):
        refined = []
        for a, b in zip(points[:-1], points[1:]):
            third = (b - a) / 3
            refined += [a, a + third, a + third - turn.T @ third, a + 2 * third]
        points = refined + [points[-1]]
    return silhouettes._inside(Path(np.array(points)), size)


def test_a_thin_limbed_creature_looks_porous_but_a_blob_does_not():
    creature = ifslib.load_target(silhouettes.limbed(128, seed=2, width=0.03).astype(float), 128)
    blob = ifslib.load_target(silhouettes.blob(128, seed=2).astype(float), 128)
    assert auto.classify(creature) == "shape"
    assert plan.FIGURE.ambiguous_share <= auto.interior_share(creature) < auto.FIGURE.porous_share <= auto.interior_share(blob)
    assert len(silhouettes.thin_gallery(32)) == 6


def test_ambiguous_reads_the_chosen_iou_at_full_precision_and_the_figure_share():
    creature = ifslib.load_target(silhouettes.limbed(128, seed=2, width=0.03).astype(float), 128)
    why = plan.ambiguous(auto.interior_share(creature), 5, 0.85)
    assert why is not None and "IoU 0.850" in why and "5 maps" in why and "fitted as a fractal and as a shape" in why
    assert plan.ambiguous(auto.interior_share(creature), 5, plan.FIGURE.clear_fractal_iou) is None
    # just below the bar is below it, though it would round up to the bar in the file
    assert plan.ambiguous(auto.interior_share(creature), 5, plan.FIGURE.clear_fractal_iou - 1e-6) is not None
    lace = ifslib.load_target(ifslib.render(ifslib.random_fractals.random_ifs(3, 1), 128, method="chaos",
                                            points=200_000, seed=1).numpy(), 128)
    assert auto.interior_share(lace) < plan.FIGURE.ambiguous_share
    # a lace is a fractal however poorly it was found
    assert plan.ambiguous(auto.interior_share(lace), 3, 0.5) is None


@pytest.mark.parametrize("kwargs, message", [({"limbs": -1}, "limbs must be an integer >= 0"),
                                             ({"holes": 1.5}, "holes must be an integer >= 0"),
                                             ({"width": 0.0}, "width must be a number between 0 and 0.5"),
                                             ({"width": True}, "width must be a number")])
def test_limbed_refuses_bad_drawings(kwargs, message):
    with pytest.raises(ValueError, match=message):
        silhouettes.limbed(32, **kwargs)


def test_limbed_draws_its_parts():
    from scipy import ndimage

    bare = silhouettes.limbed(96, seed=0, limbs=0, tail=False, holes=0)
    full = silhouettes.limbed(96, seed=0, limbs=4, tail=True, holes=1)
    assert ndimage.label(bare)[1] == 1 and not (ndimage.binary_fill_holes(bare) & ~bare).any()
    assert (ndimage.binary_fill_holes(full) & ~full).sum() > 10  # the hole stays a hole
    assert full.sum() > bare.sum() - 200  # the limbs and the tail add more than the hole takes
    assert np.array_equal(full, silhouettes.limbed(96, seed=0, limbs=4, tail=True, holes=1))


def test_a_figure_that_may_be_a_shape_is_searched_once(searches):
    from ifslib.automatic import fractal

    creature = ifslib.load_target(silhouettes.limbed(128, seed=2, width=0.03).astype(float), 128)
    lace = ifslib.load_target(ifslib.render(ifslib.random_fractals.random_ifs(3, 1), 128, method="chaos",
                                            points=200_000, seed=1).numpy(), 128)
    assert plan.discover(creature, maps=4, depth=2).kind == "shape"
    assert plan.discover(lace, maps=4, depth=2).kind == "shape"
    assert [c for _, c in searches] == [AUTO.ambiguous_search, fractal.DEFAULT] and AUTO.ambiguous_search.again == 0


def test_the_edge_dimension_is_one_for_smooth_edges_and_more_for_fractal_ones(overlap):
    square = np.zeros((128, 128), bool)
    square[20:100, 30:110] = True
    disk = np.hypot(*np.mgrid[-1:1:128j, -1:1:128j]) < 0.7
    for smooth in (square, disk):
        assert abs(auto.edge_dimension(target_from_mask(smooth)) - 1.0) < 0.02
    snowflake = target_from_mask(_koch_snowflake(256))
    assert 1.1 < auto.edge_dimension(snowflake) < np.log(4) / np.log(3) + 0.02  # below the limit's, drawn in pixels
    drawn = silhouettes.gallery(128)
    assert max(auto.edge_dimension(target_from_mask(m)) for m in drawn.values()) < auto.FIGURE.rough_edge
    assert auto.interior_share(overlap) >= auto.FIGURE.porous_share and auto.edge_dimension(overlap) >= auto.FIGURE.rough_edge
    assert auto.thin_share(overlap) <= auto.FIGURE.thin_parts  # rough at every scale, not for thin parts


def test_thin_parts_are_those_an_opening_removes():
    square = np.zeros((128, 128), bool)
    square[40:80, 20:60] = True  # a 40 px square: the disk rounds its corners off, a few pixels each
    corners = auto.thin_share(target_from_mask(square)) * 1600
    assert 0 < corners <= 4 * 9
    limbed = square.copy()
    limbed[58:62, 60:100] = True  # and a 4 px wide limb of 160 pixels: thin, but for a few pixels at its root
    assert 150 <= auto.thin_share(target_from_mask(limbed)) * (1600 + 160) - corners <= 160
    creature = ifslib.load_target(silhouettes.limbed(128, seed=1).astype(float), 128)
    assert auto.edge_dimension(creature) >= auto.FIGURE.rough_edge and auto.thin_share(creature) > auto.FIGURE.thin_parts


def test_a_solid_figure_is_searched_when_its_edge_is_rough(searches, overlap):
    blob = ifslib.load_target(silhouettes.blob(128, seed=2).astype(float), 128)
    assert plan.discover(blob, maps=4, depth=2).kind == "shape" and searches == []
    limbs = ifslib.load_target(silhouettes.thin_gallery(128)["creature 1"].astype(float), 128)  # rough for its limbs
    assert auto.interior_share(limbs) >= auto.FIGURE.porous_share and auto.edge_dimension(limbs) >= auto.FIGURE.rough_edge
    assert plan.discover(limbs, maps=4, depth=2).kind == "shape" and searches == []
    found = plan.discover(overlap, maps=4, depth=2)
    # searched once: a shape fit to fall back on
    assert found.kind == "shape" and [c for _, c in searches] == [AUTO.ambiguous_search]
    assert found.pattern["fractal_search"]["edge_dimension"] == round(auto.edge_dimension(overlap), 3)
    why = plan.ambiguous(auto.interior_share(overlap), 3, 0.9, auto.edge_dimension(overlap))
    assert "solid (interior share" in why and "rough edge" in why and "fitted as a fractal and as a shape" in why


def test_a_limbed_figure_has_maps_squeezed_onto_its_thin_parts():
    from scipy import ndimage

    creature = ifslib.load_target(silhouettes.thin_gallery(128)["creature 1"].astype(float), 128)
    share, thin = auto.interior_share(creature), auto.thin_share(creature)
    assert auto.detailed(share, 128) and auto.limbed(share, thin, 128)
    k = 24
    n = auto.limb_maps(creature, k)
    assert 2 <= n <= k // 2
    maps = auto.shape_maps(creature, k, limbs=True)
    assert maps.shape == (k, 2, 3) and not np.array_equal(maps, auto.shape_maps(creature, k))
    # each map takes the figure's mean onto its part's mean: the last n onto the thin parts (within a curved
    # limb's bend), the others onto the body
    mean = auto.foreground_points(creature).mean(0)
    centres = maps[:, :, :2] @ mean + maps[:, :, 2]
    cols = np.clip(((centres[:, 0] + 0.5) * 128).astype(int), 0, 127)
    rows = np.clip(((0.5 - centres[:, 1]) * 128).astype(int), 0, 127)
    off_thin = ndimage.distance_transform_edt(~auto.thin_parts(creature))
    assert (off_thin[rows[-n:], cols[-n:]] <= 3).all() and (off_thin[rows[:-n], cols[:-n]] > 0).mean() > 0.9
    # squeezed across the limb: the thin maps' smaller singular value is below the body maps'
    smallest = np.linalg.svd(maps[:, :, :2], compute_uv=False)[:, -1]
    assert np.median(smallest[-n:]) < np.median(smallest[:-n])


def test_a_figure_without_thin_parts_keeps_its_maps_and_a_detailed_one_is_offered_more(searches):
    blob = ifslib.load_target(silhouettes.blob(128, seed=2).astype(float), 128)
    assert auto.limb_maps(blob, 24) == 0
    assert np.array_equal(auto.shape_maps(blob, 24, limbs=True), auto.shape_maps(blob, 24))
    assert not auto.detailed(auto.interior_share(blob), 128)
    chosen = plan.discover(blob)
    assert [len(c.rules) for c in chosen.candidates] == [k for k, _ in auto.START.shape_choices]
    assert "limb_maps" not in chosen.pattern
    creature = ifslib.load_target(silhouettes.thin_gallery(128)["creature 1"].astype(float), 128)
    chosen = plan.discover(creature)
    assert [(len(c.rules), c.depth) for c in chosen.candidates] == list(auto.START.shape_choices_detailed)
    assert auto.shape_detail(creature) == (True, True) and auto.shape_detail(blob) == (False, False)
    assert [c.meta["pattern"]["limb_maps"] for c in chosen.candidates] == [
        auto.limb_maps(creature, k) for k, _ in auto.START.shape_choices_detailed]
    # a number of maps given is kept; the paper's carpet, a lace of thin parts, is not a detailed shape at 128², and
    # at 64² (where its interior share, read from an enlarged drawing, is 0.71) too small to be one
    assert auto.choices("shape", maps=5, detail=True) == [(5, auto.START.default_depth)]
    for size in (64, 128):
        carpet = ifslib.load_target("sierpinski", size)
        assert auto.thin_share(carpet) > auto.FIGURE.thin_parts and not auto.detailed(auto.interior_share(carpet), size)
    small = ifslib.load_target(silhouettes.thin_gallery(64)["creature 1"].astype(float), 64)
    assert [len(c.rules) for c in plan.discover(small).candidates] == [k for k, _ in auto.START.shape_choices]


def test_a_porous_figure_with_a_smooth_edge_is_not_searched(searches):
    thin = silhouettes.thin_gallery(128)
    y = ifslib.load_target(thin["thin letter Y"].astype(float), 128)
    share = auto.interior_share(y)
    assert plan.FIGURE.ambiguous_share <= share < auto.FIGURE.porous_share and auto.edge_dimension(y) < auto.FIGURE.rough_edge
    chosen = plan.discover(y, maps=4, depth=2)
    assert chosen.kind == "shape" and searches == []
    assert "smooth edge (dimension 1.0" in chosen.pattern["not_searched"] and "fractal_search" not in chosen.pattern
    # a porous figure whose edge is rough (here for its limbs) is searched, and so is a lace whatever its edge
    creature = ifslib.load_target(thin["creature 2"].astype(float), 128)
    assert plan.FIGURE.ambiguous_share <= auto.interior_share(creature) < auto.FIGURE.porous_share
    assert auto.edge_dimension(creature) >= auto.FIGURE.rough_edge
    assert "not_searched" not in plan.discover(creature, maps=4, depth=2).pattern
    assert [t for t, _ in searches] == [creature]
    lace = ifslib.load_target(ifslib.render(ifslib.random_fractals.random_ifs(3, 1), 128, method="chaos",
                                            points=200_000, seed=1).numpy(), 128)
    plan.discover(lace, maps=4, depth=2)
    assert [t for t, _ in searches] == [creature, lace]


@pytest.mark.slow
def test_the_automatic_start_of_a_two_map_fractal_is_its_maps_and_a_silhouette_stays_a_shape():
    _, target = fractal_target(maps=2, seed=4, size=128)
    assert auto.interior_share(target) < auto.FIGURE.porous_share
    plan = ifslib.discover(target, maps=2)  # the search, with its number of maps fixed
    start, pattern = plan.start, plan.pattern
    assert plan.kind == "fractal" and plan.candidates == (start,) and pattern == start.meta["pattern"]
    assert pattern["kind"] == "fractal" and len(start.rules) == 2
    assert [row["maps"] for row in pattern["search"]] == [2] and "minimum description length" in pattern["rule"]
    m = ifslib.evaluate(start, target, depth="attractor")
    assert m["iou"] >= 0.85 and m["chamfer"] <= 1.0
    row = pattern["search"][0]  # the rule's score: 1 - the attractor's IoU (chaos game) plus the cost of its maps
    assert abs(row["iou"] - m["iou"]) < 0.03 and abs(row["score"] - (1 - row["iou"] + fractal.DEFAULT.map_cost * 2)) <= 1.0001e-4  # each rounded once
    # the auto strategy sends it straight to the attractor stage and records the search's table
    fitted = ifslib.fit(plan, target, steps=5, progress=False)
    assert fitted.history.strategy == "auto"
    assert fitted.history.kind == fitted.history.auto.kind == "fractal" and fitted.history.auto.chosen == 2
    assert [(c.maps, c.by, round(c.value, 4)) for c in fitted.history.auto.candidates] == [
        (r["maps"], "score", r["score"]) for r in pattern["search"]]  # the search's rows, in the candidates' layout
    assert [st.depth for st in fitted.history.stages] == ["attractor"] and fitted.history.cost <= 5
    # the single-scale pixel loss: the distance loss trades thin detail for the outline, the multiscale one blurs it
    assert fitted.history.stages[0].loss == "pixel" == automatic.FIT.fractal_loss
    assert fitted.best.meta["pattern"]["rule"] == pattern["rule"]
    disk = np.hypot(*np.mgrid[-1:1:64j, -1:1:64j]) < 0.7
    assert auto.interior_share(target_from_mask(disk)) > auto.FIGURE.porous_share


def test_discover_refuses_a_bad_jitter_before_any_search():
    target = ifslib.load_target(ifslib.patterns.koch(depth=2), 32)
    with pytest.raises(ifslib.IFSError, match="jitter must be a number from 0 to 1"):
        ifslib.discover(target, jitter=1.5)


def test_the_learned_guess_is_kept_only_when_its_attractor_scores_less(monkeypatch):
    truth, target = fractal_target(maps=2, seed=4, size=128)
    found = fractal.search(target, 2, progress=False)
    import ifslib.learned.estimator as learned

    monkeypatch.setattr(learned, "guess_maps", lambda mask: truth.maps()[:, :2].detach().double().numpy())
    exact = plan.with_learned(target, found, fractal.DEFAULT)
    assert exact.learned and np.allclose(exact.maps, truth.maps()[:, :2].detach().double().numpy())
    assert exact.choice is exact.rows[-1] and exact.choice.learned and exact.choice.score <= found.choice.score
    assert exact.rows[:-1] == found.rows and "the guess kept" in exact.rule
    assert exact.table[-1]["learned"] is True and "learned" not in exact.table[0]
    far = np.array([[[0.3, 0, 0.3], [0, 0.3, 0.3]], [[0.3, 0, -0.3], [0, 0.3, 0.3]]])
    monkeypatch.setattr(learned, "guess_maps", lambda mask: far)
    kept = plan.with_learned(target, found, fractal.DEFAULT)
    assert not kept.learned and kept.maps is found.maps and kept.choice is found.choice
    assert "the search kept" in kept.rule


def test_discover_refuses_a_learned_that_is_not_a_bool():
    target = ifslib.load_target(ifslib.patterns.koch(depth=2), 32)
    with pytest.raises(ifslib.IFSError, match="learned must be True or False"):
        ifslib.discover(target, learned="yes")
