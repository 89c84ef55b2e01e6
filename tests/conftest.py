"""Shared helpers for the tests: small random IFSs of every rule and primitive kind, and ``--device``.

``pytest --device cuda`` runs the device-aware tests (those taking the ``device`` fixture: fast
against brute force, gradients, batched fields, fits) on the GPU; without CUDA they are skipped.
The default is ``cpu``.
"""
import math
import os
import re

import pytest

import ifslib
from ifslib import threads as _threads  # noqa: F401 - first: it sets OpenMP's wait policy before torch loads
import torch  # noqa: E402


def perturbed(ifs, scale=0.01, seed=0, dtype=torch.float64):
    """A copy of ``ifs`` with its points jittered by U(-scale, scale), in ``dtype``."""
    g = torch.Generator().manual_seed(seed)
    pts = ifs.points.detach().double() + (torch.rand(ifs.points.shape, generator=g, dtype=torch.float64) * 2 - 1) * scale
    return ifs.to(dtype).clone(pts.to(dtype))


def mixed(depth=2, dtype=torch.float64):
    """Segment rules drawing a thick segment, a disk and a box: every primitive kind, rotations included."""
    s = math.sqrt(3) / 6
    points = [[-0.4, -0.1], [-0.1, -0.1], [0.0, -0.1 + 0.8 * s], [0.1, -0.1], [0.4, -0.1],
              [0.05, 0.2], [-0.2, 0.1], [-0.1, 0.25]]
    rules = [{"kind": "segment", "from": [0, 4], "to": [i, i + 1]} for i in range(4)]
    prims = [{"kind": "segment", "points": [0, 4], "radius": 0.01},
             {"kind": "disk", "points": [5], "radius": 0.06},
             {"kind": "box", "points": [6, 7]}]
    return ifslib.IFS(points, rules, prims, depth=depth, dtype=dtype)


def sheared(primitive="box", depth=2, dtype=torch.float64):
    """Three general affine maps: non-uniform scale, shear and a reflection (det < 0)."""
    maps = [[[0.45, 0.12, -0.22], [0.0, 0.3, -0.2]],      # non-uniform scale with a shear
            [[0.2, -0.25, 0.25], [0.3, 0.15, -0.1]],      # rotation with unequal axes
            [[0.4, 0.05, 0.0], [0.1, -0.35, 0.25]]]       # a reflection
    return ifslib.patterns.affine(maps, depth=depth, primitive=primitive, dtype=dtype)


def sheared_mixed(depth=2, dtype=torch.float64):
    """The sheared maps drawing a thick segment, a disk and a box (every primitive kind under affine maps)."""
    base = sheared(depth=depth, dtype=dtype)
    points = torch.cat([base.points.detach(), torch.tensor([[-0.3, -0.2], [0.25, 0.1], [0.1, 0.3]], dtype=dtype)])
    prims = [{"kind": "segment", "points": [4 + 9, 4 + 10], "radius": 0.02}, {"kind": "disk", "points": [4 + 11], "radius": 0.1},
             {"kind": "box", "points": [0, 3]}]
    return ifslib.IFS(points, base.rules, prims, depth=depth, fixed=base.fixed, dtype=dtype)


def sheared_disks(depth=2, dtype=torch.float64):
    """The sheared maps drawing a disk alone (one kind under affine maps)."""
    base = sheared(depth=depth, dtype=dtype)
    points = torch.cat([base.points.detach(), torch.tensor([[0.05, 0.1]], dtype=dtype)])
    prims = [{"kind": "disk", "points": [len(points) - 1], "radius": 0.1}]
    return ifslib.IFS(points, base.rules, prims, depth=depth, fixed=base.fixed, dtype=dtype)


PATTERNS = {
    "affine": lambda: sheared(),
    "affine_mixed": lambda: sheared_mixed(),
    "koch": lambda: ifslib.patterns.koch(),
    "carpet": lambda: ifslib.patterns.sierpinski_carpet(),
    "grid2": lambda: ifslib.patterns.grid(2),
    "mixed": lambda: mixed(),
}


@pytest.fixture(params=sorted(PATTERNS))
def pattern_name(request):
    return request.param


# The notebooks' kernels (tests/notebooks/test_notebook_runs.py) inherit this environment: one torch thread
# unless the caller chose a count, which suits make test's two pytest-xdist workers on a 2-core machine;
# and matplotlib's inline backend, as a reader's Jupyter has it (CI exports MPLBACKEND=Agg, under which a
# notebook's figure cells would show nothing).
os.environ.pop("MPLBACKEND", None)
os.environ.setdefault("IFSLIB_THREADS", "1")


#: Test modules kept on one worker: their module fixture draws for about 11 s (the literature's IFS classes).
WHOLE_MODULES = {"tests/benchmarks/test_samplers.py"}


def notebook_scope(nodeid: str) -> str:
    """The work unit of a test under ``make test``'s pytest-xdist workers (``-n auto --dist loadscope``).

    A notebook's run and the comparison of its figure (tests/notebooks/test_notebook_runs.py, both
    parametrized by the notebook's name) are one unit, so that the figure is compared on the worker
    that ran the notebook, without a second run. A module whose module-scoped fixture is costly
    (`WHOLE_MODULES`) is one unit, so that one worker builds the fixture. Every other test is a unit
    of its own, so the workers stay evenly loaded.
    """
    path, _, rest = nodeid.partition("::")
    if path in WHOLE_MODULES:
        return path
    run = re.fullmatch(r"test_(?:runs_at_quick_values|figure_matches_reference)\[(.+)\]", rest)
    if path.endswith("test_notebook_runs.py") and run:
        return run.group(1)
    return nodeid


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_auto_num_workers(config):
    """``-n auto``: as many workers as the cores hold at ``IFSLIB_THREADS`` threads each (one thread by default).

    ``IFSLIB_THREADS=2 make test`` on 2 cores then runs one worker: two workers at two threads each
    would oversubscribe the cores, and torch's waiting threads slow every test several times over.
    """
    from ifslib.threads import cores

    value = os.environ.get("IFSLIB_THREADS", "")
    threads = int(value) if value.strip().isdigit() else 1  # "auto" follows the free cores: one each
    return max(1, cores() // max(1, threads))


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """``--dist loadscope`` with `notebook_scope`'s units (pytest 9's node ids defeat xdist's ``loadgroup`` marks)."""
    if config.getvalue("dist") != "loadscope":
        return None
    from xdist.scheduler import LoadScopeScheduling

    class NotebookScheduling(LoadScopeScheduling):
        def _split_scope(self, nodeid: str) -> str:
            return notebook_scope(nodeid)

    return NotebookScheduling(config, log)


def pytest_collection_modifyitems(config, items):
    """Mark the notebooks' runs ``notebook`` (``tests/notebooks/``), so that ``make test-fast``
    (``-m "not notebook and not slow"``) leaves them out, and put them first, the longest first
    (notebooks/run.py's ``LONGEST``): the workers start on the long units and finish together."""
    folder = f"{os.sep}tests{os.sep}notebooks{os.sep}"
    for item in items:
        if folder in str(item.fspath):
            item.add_marker(pytest.mark.notebook)

    def rank(item):
        scope = notebook_scope(item.nodeid)
        if scope == item.nodeid:  # not a notebook's run
            return 1, 0
        return 0, next((k for k, p in enumerate(NOTEBOOK_LONGEST) if scope.startswith(p)), len(NOTEBOOK_LONGEST))

    items.sort(key=rank)  # a stable sort: each notebook's run stays before its figure's comparison


#: notebooks/run.py's ``LONGEST`` at the quick values (docs/results/tests.md), longest first.
NOTEBOOK_LONGEST = ("07_", "11_", "02_", "08_", "04_", "05_", "00_tutorial", "06_", "01_", "03_")


def pytest_addoption(parser):
    parser.addoption("--device", default="cpu",
                     help="torch device of the device-aware tests: cpu (default) or cuda (skipped without CUDA)")


@pytest.fixture
def device(request):
    """The ``--device`` option; skips the test when it asks for CUDA and none is present."""
    name = request.config.getoption("--device")
    if name.startswith("cuda") and not torch.cuda.is_available():
        pytest.skip("--device cuda, but torch finds no CUDA device")
    return name
