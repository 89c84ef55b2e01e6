"""The fractal search: copies that fit inside (against brute force), maps in plane units, the collage,
reorienting, the whole search on a small random fractal, the automatic start, bad input."""
from dataclasses import replace

import numpy as np
import pytest
import torch

import ifslib
from ifslib.errors import IFSError
from ifslib.discovery import auto, fractal
from ifslib.discovery.fractal import candidates, driver
from ifslib.fitting import automatic
from ifslib.targets.target import foreground_points, resize_target, target_from_mask


def fractal_target(maps=2, seed=4, size=64):
    """A random fractal (`ifslib.patterns.random_ifs`) drawn by the float64 chaos game at 256², as the benchmark
    draws them, then made ``size`` pixels wide as a fit does (`resize_target`)."""
    truth = ifslib.patterns.random_ifs(maps, seed)
    mask = ifslib.render(truth, 256, method="chaos", points=1_000_000, seed=seed).numpy() >= 0.5
    return truth, resize_target(target_from_mask(mask, f"random{maps}_{seed}"), size)


def test_the_linear_grid_is_its_formula_in_order_entry_by_entry():
    turns, phases, scales, ratios = 5, 3, (0.3, 0.7), (0.5, 1.0)
    expected = [fractal.rotation(theta) @ np.diag([s, sign * r * s]) @ fractal.rotation(phi)
                for s in scales for r in ratios for phi in ([0.0] if r == 1.0 else np.arange(phases) * np.pi / phases)
                for theta in np.arange(turns) * 2 * np.pi / turns for sign in (1.0, -1.0)]
    grid = fractal.linear_grid(turns=turns, phases=phases, scales=scales, ratios=ratios)
    assert grid.shape == (len(expected), 2, 2) == (2 * (3 + 1) * 5 * 2, 2, 2)
    np.testing.assert_array_equal(grid, np.array(expected))
    s = np.linalg.svd(grid, compute_uv=False)
    assert np.allclose(s[:, 0], np.repeat(scales, len(grid) // 2))  # the larger singular value is the scale


def test_copy_candidates_count_the_copy_pixels_on_the_grown_figure_as_brute_force_does():
    from scipy import ndimage

    _, target = fractal_target(size=32)
    grid = fractal.linear_grid(turns=4, phases=2, scales=(0.45, 0.75), ratios=(0.5, 1.0))
    cands = fractal.copy_candidates(target.mask, grid, per_map=3, config=replace(fractal.DEFAULT, inside=0.0))
    grown = ndimage.binary_dilation(target.mask)
    pts = candidates.pixels(target.mask)
    u = pts - pts.mean(0)
    assert len(cands) > 0
    for hits, g, row, col in cands[:40]:
        v = np.round(u @ grid[g].T).astype(int)
        drawn = {(row - y, col + x) for x, y in v}  # pixel (x, y) = (col, -row)
        on = sum(0 <= r < 32 and 0 <= c < 32 and grown[r, c] for r, c in drawn)
        assert on == hits


def test_copy_candidates_count_every_placement_as_brute_force_does_even_for_a_figure_in_a_corner():
    # every placement of every copy (per_map: all of them) counted by hand and ranked by the same exact key: the
    # FFT's padding, sized to the copies' reach, must never wrap a copy's pixels back onto the figure
    from scipy import ndimage

    _, target = fractal_target(size=24)
    mask = np.zeros((24, 24), bool)
    mask[:18, 6:] = target.mask[3:21, :18]  # pushed to the top right: copies reach past the frame
    grid = fractal.linear_grid(turns=6, phases=2, scales=(0.35, 0.85), ratios=(0.4, 1.0))
    config = replace(fractal.DEFAULT, inside=0.6)
    cands = fractal.copy_candidates(mask, grid, per_map=576, chunk=7, config=config)
    padded = np.pad(ndimage.binary_dilation(mask), 24)
    u = candidates.pixels(mask) - candidates.pixels(mask).mean(0)
    expected = []
    for g, linear in enumerate(grid):
        drawn = {(-y, x) for x, y in np.round(u @ linear.T).astype(int)}  # offsets (row, col) from the centroid
        hits = sum(padded[24 + dr:48 + dr, 24 + dc:48 + dc].astype(int) for dr, dc in drawn).ravel()
        key = np.where(hits >= config.inside * len(drawn) - 0.5, hits, 0) * 576 + (575 - np.arange(576))
        value = np.sort(key)[::-1]
        count, index = value // 576, 575 - value % 576
        expected += [(k, g, i // 24, i % 24) for k, i in zip(count, index) if k >= 1]
    expected = np.array(expected)
    np.testing.assert_array_equal(cands, expected[np.argsort(-expected[:, 0], kind="stable")])


def test_plane_maps_send_the_figure_centroid_to_the_candidate_pixel():
    _, target = fractal_target(size=32)
    grid = fractal.linear_grid(turns=4, phases=2, scales=(0.5,), ratios=(0.5, 1.0))
    cands = fractal.copy_candidates(target.mask, grid, config=replace(fractal.DEFAULT, inside=0.0))[:10]
    centroid = candidates.pixels(target.mask).mean(0)
    maps = fractal.plane_maps(grid, cands, centroid, 32)
    mu = foreground_points(target).mean(0)  # the same centroid, in plane units
    for m, (_, g, row, col) in zip(maps, cands):
        np.testing.assert_allclose(m[:, :2], grid[g])
        np.testing.assert_allclose(m[:, :2] @ mu + m[:, 2], [(col + 0.5) / 32 - 0.5, 0.5 - (row + 0.5) / 32], atol=1e-12)


def test_collage_is_least_for_the_true_maps_and_refine_keeps_scales_in_range():
    truth, target = fractal_target(size=64)
    true_maps = truth.maps().detach().double()[:, :2].numpy()
    shifted = true_maps.copy()
    shifted[0, :, 2] += 0.03
    _, error = fractal.refine(np.stack([true_maps, shifted]), target, 0, 0.0, 2000)
    assert error[0] < 0.6 and error[1] > 1.5 * error[0]  # pixels
    wild = true_maps.copy()
    wild[0, :, :2] *= 1.5  # scale > 1: clipped back into range
    work, _ = fractal.refine(wild[None], target, 5, 0.002, 500)
    s = torch.linalg.svdvals(work[0, :, :, :2])
    assert float(s.max()) <= fractal.DEFAULT.max_scale + 1e-5 and float(s.min()) >= fractal.DEFAULT.min_scale - 1e-6


def test_collage_sets_find_the_least_collage_set_of_a_small_pool_as_brute_force_does():
    """Greedy plus swaps against every set of a small pool: the set with the least collage distance is found,
    and it is the true maps hidden among perturbed copies of them."""
    from itertools import combinations

    truth, target = fractal_target(maps=3, seed=1, size=64)
    true_maps = truth.maps().detach().double()[:, :2].numpy()
    rng = np.random.default_rng(0)
    pool = [true_maps[i % 3] + rng.normal(0, 0.04, (2, 3)) * (i >= 3) for i in range(18)]  # 0-2: the truth
    pool = np.array(pool)
    every_pixel = replace(fractal.DEFAULT, restarts=6, collage_points=(64 * 64, 2000))
    sets = fractal.collage_sets(pool, target, [2, 3], config=every_pixel)

    fg = foreground_points(target)
    for k in (2, 3):
        combos = np.array(list(combinations(range(len(pool)), k)))
        outside, cover = fractal.collage_terms(torch.as_tensor(pool[combos], dtype=torch.float32),
                                               torch.as_tensor(fg, dtype=torch.float32), target.distance.float())
        brute = combos[int(torch.argmin(outside + cover))]
        assert sets[k][0] == sorted(brute.tolist())
        assert len({tuple(s) for s in sets[k]}) == len(sets[k])  # distinct
    assert sets[3][0] == [0, 1, 2]


@pytest.mark.slow
def test_turns_keep_the_figure_mean_and_covariance_and_reorient_undoes_a_turned_map():
    truth, target = fractal_target(size=64)
    fg = foreground_points(target)
    for s in fractal.turns(target):
        moved = fg @ s[:, :2].T + s[:, 2]
        np.testing.assert_allclose(moved.mean(0), fg.mean(0), atol=1e-9)
        np.testing.assert_allclose(np.cov(moved.T), np.cov(fg.T), atol=1e-9)
    true_maps = truth.maps().detach().double()[:, :2].numpy()
    _, truth_error = fractal.refine(true_maps[None], target, 0, 0.0, 2000)
    turned = true_maps.copy()
    s = fractal.turns(target)[11]  # a half turn
    turned[1, :, :2] = true_maps[1, :, :2] @ s[:, :2]
    turned[1, :, 2] = true_maps[1, :, :2] @ s[:, 2] + true_maps[1, :, 2]
    _, turned_error = fractal.refine(turned[None], target, 0, 0.0, 2000)
    maps, error = fractal.reorient(turned, target)
    assert float(turned_error[0]) > 1.5 * float(truth_error[0])
    assert error <= 1.1 * float(truth_error[0])


@pytest.mark.slow
def test_the_automatic_start_of_a_two_map_fractal_is_its_maps_and_a_silhouette_stays_a_shape():
    _, target = fractal_target(maps=2, seed=4, size=128)
    assert auto.interior_share(target) < auto.FIGURE.porous_share
    plan = ifslib.initialize("auto", target, maps=2)  # the search, with its number of maps fixed
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


def test_fractal_search_refuses_bad_numbers_of_maps_and_figures_with_no_copy(monkeypatch):
    _, target = fractal_target(size=32)
    for bad in (0, fractal.DEFAULT.max_maps + 1, 2.5):
        with pytest.raises(IFSError, match="maps"):
            fractal.search(target, maps=bad, progress=False)
    # a figure none of whose copies lies inside it (the candidates stood in for: the counts are exact, so which
    # figures have none is a matter of the grid, and a two-pixel speck has some; see test_determinism.py)
    monkeypatch.setattr(candidates, "copy_candidates", lambda mask, grid, **_: np.zeros((0, 4), np.int64))
    with pytest.raises(IFSError, match="no copy of the figure fits inside it"):
        fractal.search(target, maps=2, progress=False)


def test_search_compares_the_numbers_of_maps_given_and_sampled_leaves_refuse_a_map_near_scale_one():
    assert fractal.check_maps(None) == fractal.DEFAULT.fractal_maps
    assert fractal.check_maps([3, 2, 3]) == (2, 3)
    with pytest.raises(IFSError, match="at least one"):
        fractal.check_maps([])
    from ifslib.geometry.sampled import MAX_WORD_LENGTH, sample_attractor

    slow = torch.eye(3, dtype=torch.float64).repeat(2, 1, 1)
    slow[0, :2, :2] *= 0.99999
    slow[1, :2, :2] *= 0.5
    slow[1, :2, 2] = 0.2
    with pytest.raises(IFSError, match=f"more than {MAX_WORD_LENGTH}"):
        sample_attractor(slow, 1e-3, 64)


def test_chaos_occupancy_marks_the_pixels_of_the_float64_chaos_game_for_a_batch():
    from ifslib.geometry.attractor import chaos_probabilities
    from ifslib.raster.chaos import chaos_game, chaos_occupancy

    systems = [ifslib.patterns.random_ifs(3, 1), ifslib.patterns.random_ifs(3, 5)]
    maps = torch.stack([s.maps().detach() for s in systems])
    batched = chaos_probabilities(maps)
    for one, s in zip(batched, systems):  # a batch is normalised one IFS at a time, as each alone
        torch.testing.assert_close(one, chaos_probabilities(s.maps()))
    drawn = chaos_occupancy(maps[:, :, :2, :], 64, chains=100, steps=200).numpy()
    for picture, s in zip(drawn, systems):
        points = chaos_game(s, 400_000)
        col, row = np.floor((points[:, 0] + 0.5) * 64).astype(int), np.floor((0.5 - points[:, 1]) * 64).astype(int)
        inside = (col >= 0) & (col < 64) & (row >= 0) & (row < 64)
        reference = np.zeros((64, 64), bool)
        reference[row[inside], col[inside]] = True
        assert (picture & ~reference).sum() <= 0.01 * picture.sum()  # float32 points stay on the attractor's pixels
        assert ifslib.iou(picture, reference) >= 0.85  # 20,000 points find most of them
    with pytest.raises(IFSError, match="shape"):
        chaos_occupancy(maps[0], 64)


@pytest.mark.slow
def test_swap_puts_back_a_map_that_the_sets_of_copies_left_out():
    truth, target = fractal_target(maps=3, seed=1, size=128)
    coarse = resize_target(target, 64)
    true_maps = truth.maps().detach().double()[:, :2].numpy()
    wrong = true_maps.copy()
    wrong[2] = [[0.3, 0.0, -0.2], [0.0, 0.3, 0.2]]  # a small copy in the wrong place
    rng = np.random.default_rng(0)
    pool = np.concatenate([fractal.random_starts(60, 1, coarse, rng)[:, 0], true_maps[2:] + 0.004])
    best, before = fractal.attractor_iou(true_maps, target), fractal.attractor_iou(wrong, target)
    maps, after, kept = fractal.swap(wrong, pool, coarse, target, target, rounds=2)
    assert before < 0.2 and kept >= 1 and after >= best - 0.03  # as close as the true maps' attractor
    assert after == pytest.approx(fractal.attractor_iou(maps, target), abs=0.02)
    assert np.abs(maps - true_maps).max() < 0.02  # the true map, found in the pool, and the others kept


def test_search_runs_again_from_the_next_seed_only_while_no_attractor_fits(monkeypatch):
    """`search` wraps one search (`_search`): run again from the next seed when no attractor reaches `swap_below`,
    and the search whose chosen maps score least kept (the searches themselves are stood in for)."""
    _, target = fractal_target(size=32)
    ious = {0: 0.6, 1: 0.7, 5: fractal.DEFAULT.swap_below}
    calls = []

    copies = set()

    def one(context, ks, progress, title):
        seed, config = context.seed, context.config
        calls.append(seed)
        copies.add(id(context.copies))  # the candidate copies do not depend on the seed: found once, read again
        row = fractal.Row(maps=2, cover=1.0, collage_px=0.0, iou=ious[seed], score=1 - ious[seed] + config.map_cost * 2,
                          reoriented=seed != 7)
        return fractal.SearchResult(np.full((2, 2, 3), seed / 10), (row,), f"rule {seed}")

    monkeypatch.setattr(driver, "_search", one)
    found = fractal.search(target, maps=2, seed=0, progress=False)
    assert calls == [0, 1] and found.maps[0, 0, 0] == 0.1 and len(copies) == 1
    assert found.rule.startswith("rule 1") and "seeds 0-1" in found.rule and "0.480, 0.380" in found.rule
    calls.clear()
    once = replace(fractal.DEFAULT, again=0)
    assert fractal.search(target, maps=2, seed=0, progress=False, config=once).rule == "rule 0" and calls == [0]
    calls.clear()
    found = fractal.search(target, maps=2, seed=5, progress=False)  # an attractor that fits: one search
    assert calls == [5] and found.rule == "rule 5"
    calls.clear()
    ious[7] = 0.3
    found = fractal.search(target, maps=2, seed=7, progress=False)  # gave up before reorienting: not a fractal
    assert calls == [7] and found.rule == "rule 7"
