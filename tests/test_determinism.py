"""The same answer at any thread count: fits run in fresh processes at 1 and 2 threads, their files compared.

Each run is a subprocess with ``IFSLIB_THREADS`` fixed, so the comparison crosses thread counts
whatever the machine's load; the two run at once, so each is also the other's busy neighbour (the
default ``auto`` follows the load, and with results that do not depend on the thread count, a busy
machine gives the same answer as an idle one).
"""
import json
import os
import subprocess
import sys

import numpy as np
import pytest
import torch

import ifslib
from ifslib.automatic import fractal

SEARCH = """
import hashlib, json, sys
import numpy as np
import ifslib
from dataclasses import replace
from ifslib.automatic import fractal
from ifslib.core.targets.target import resize_target, target_from_mask
truth = ifslib.random_fractals.random_ifs(2, 6)  # one whose search reorients, grows regions and swaps (below)
mask = ifslib.render(truth, 256, method="chaos", points=1_000_000, seed=4).numpy() >= 0.5
speck = np.zeros((32, 32), bool)
speck[10, 10:12] = True
# every phase and move once, at fewer steps and points: each discrete choice is still made, in a third of the time
LIGHT = replace(fractal.DEFAULT, again=0, search_steps=60, refine_steps=60, judge_points=100_000, region_rounds=1,
                grow_rounds=1, swap_rounds=1)
out = {}
for name, target in (("fractal", resize_target(target_from_mask(mask), 32)), ("speck", target_from_mask(speck))):
    found = fractal.search(target, maps=2, progress=False, config=LIGHT)
    out[name] = {"maps": found.maps.tolist(), "table": [{k: v for k, v in row.items() if k != "seconds"}
                                                       for row in found.table]}
print(json.dumps(out))
"""


def _side_by_side(runs: dict[int, list[str]]) -> dict[int, str]:
    """``python ARGS`` for each ``{threads: ARGS}``, all at once (each the other's busy neighbour): their outputs."""
    procs = {t: subprocess.Popen([sys.executable, *args], env=dict(os.environ, IFSLIB_THREADS=str(t)),
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for t, args in runs.items()}
    outs = {t: p.communicate() for t, p in procs.items()}
    for t, p in procs.items():
        assert p.returncode == 0, outs[t][1]
    return {t: out for t, (out, _) in outs.items()}


def _without_timings(value):
    if isinstance(value, dict):
        return {k: _without_timings(v) for k, v in value.items() if k != "seconds"}
    if isinstance(value, list):
        return [_without_timings(v) for v in value]
    return value


def test_a_koch_fit_writes_the_same_file_at_1_and_2_threads(tmp_path):
    # not in the slow tier: make test itself checks that a fit's file does not depend on the thread count
    out = {t: tmp_path / f"koch{t}.json" for t in (1, 2)}
    _side_by_side({t: ["-m", "ifslib", "fit", "koch", "--size", "64", "--steps", "40", "--quiet", "-o", str(path)]
                   for t, path in out.items()})
    files = [_without_timings(json.loads(out[t].read_text())) for t in (1, 2)]
    assert files[0]["meta"]["history"]["loss"]  # the fit ran its steps
    assert files[0] == files[1]


@pytest.mark.slow
def test_the_fractal_search_finds_the_same_maps_at_1_and_2_threads():
    found = [json.loads(out) for out in _side_by_side({1: ["-c", SEARCH], 2: ["-c", SEARCH]}).values()]
    moves = found[0]["fractal"]["table"][0]
    assert moves.get("reoriented") and moves.get("regions") and moves.get("swapped")  # each a discrete choice
    assert found[0] == found[1]
    # a two-pixel speck is the attractor of two maps, each of whose copies is one pixel on the speck: the
    # search must find maps whose attractor is drawn on exactly those two pixels
    assert found[0]["speck"]["table"][0]["iou"] == 1.0


def test_copies_of_a_two_pixel_speck_are_counted_exactly():
    # a linear part of scale <= 0.85 sends both pixels (0.5 px from their centroid) to one pixel: every part of
    # the grid has a one-pixel copy on the speck, and its count is exactly 1, however the FFT rounds
    speck = np.zeros((32, 32), bool)
    speck[10, 10:12] = True
    grid = fractal.linear_grid()
    cands = fractal.copy_candidates(speck, grid)
    assert len(cands) == 2 * len(grid)
    assert (cands[:, 0] == 1).all()
    assert set(map(tuple, cands[:, 2:].tolist())) <= {(9, 10), (9, 11), (10, 9), (10, 10), (10, 11), (10, 12),
                                                       (11, 10), (11, 11)}  # on the speck grown by one pixel


def test_sums_that_decide_are_the_same_at_any_thread_count():
    # the losses' image means and the attractor's point gradient were single sums that torch splits between
    # its threads; each is now a reduction whose order does not depend on them
    from ifslib.core.scoring.losses import mse

    g = torch.Generator().manual_seed(0)
    a, b = torch.rand(256, 256, generator=g), torch.rand(256, 256, generator=g)
    values = []
    saved = torch.get_num_threads()
    try:
        for threads in (1, 2, 4):
            torch.set_num_threads(threads)
            values.append(mse(a, b).item())
    finally:
        torch.set_num_threads(saved)
    assert values[0] == values[1] == values[2]
    assert values[0] == pytest.approx(float(((a - b) ** 2).double().mean()), rel=1e-6)
