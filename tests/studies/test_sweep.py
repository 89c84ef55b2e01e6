"""A tiny convergence sweep: serial and on the 2-worker process pool of ``scheduler="local"`` it gives the
same rows, with Dask installed or not."""
import math
import sys

import pytest

from ifslib import IFSError
from ifslib.studies.sweep import Cell, Setup, summarize, sweep, table

from common_testing import benchmark_module

SETUP = Setup(target="rendered", size=24, depth=2, steps=4)
CELLS = [Cell("plain", "exact", "paper"), Cell("plain", "paper", "line"), Cell("coarse_to_fine", "exact", "line")]


def strip(rows):
    return [{k: v for k, v in r.items() if k != "seconds"} for r in rows]


def test_serial_sweep_rows_and_summary(tmp_path):
    streamed = []
    rows = sweep(CELLS, [0, 1, 2], SETUP, batch=2, scheduler="serial", on_rows=streamed.append)
    assert len(rows) == 9
    assert [r for part in streamed for r in part] == rows and [len(p) for p in streamed] == [2, 1] * 3
    assert [(r["strategy"], r["gradient"], r["init"], r["seed"]) for r in rows[:3]] == \
        [("plain", "exact", "paper", 0), ("plain", "exact", "paper", 1), ("plain", "exact", "paper", 2)]
    assert all(r["steps"] == 4 for r in rows)
    assert all(math.isfinite(r["point_error"]) and r["point_error"] >= 0 for r in rows)
    summary = summarize(rows)
    assert [s["fits"] for s in summary] == [3, 3, 3]
    assert "| paper | exact | multiscale_distance | plain |" in table(summary)
    path = benchmark_module("convergence").write_csv(rows, tmp_path / "rows.csv")
    assert path.read_text().splitlines()[0].startswith("strategy,gradient,init,loss,seed,recovered")


def without_dask(monkeypatch):
    """Make ``import dask`` fail here as in a student's environment (requirements-student.txt has no Dask)."""
    for name in ("dask", "dask.distributed", "distributed"):
        monkeypatch.setitem(sys.modules, name, None)


@pytest.mark.slow
def test_local_runs_on_a_process_pool_with_the_serial_rows_without_dask(monkeypatch, capsys):
    # notebook 06's teaching value is scheduler="local": a student without Dask runs it, with no word on stderr
    without_dask(monkeypatch)
    monkeypatch.setenv("IFSLIB_PROGRESS", "0")
    seeds = [0, 1, 2]
    serial = sweep(CELLS[:2], seeds, SETUP, batch=2, scheduler="serial")
    streamed = []
    pooled = sweep(CELLS[:2], seeds, SETUP, batch=2, scheduler="local", workers=2, on_rows=streamed.append)
    assert strip(pooled) == strip(serial)
    assert sorted(len(part) for part in streamed) == [1, 1, 2, 2]  # every task's rows, in completion order
    assert sorted(map(str, strip([r for part in streamed for r in part]))) == sorted(map(str, strip(serial)))
    assert capsys.readouterr().err == ""


def test_a_scheduler_address_without_dask_is_refused_before_any_fit(monkeypatch):
    without_dask(monkeypatch)
    with pytest.raises(IFSError, match=r"Dask scheduler 'tcp://10.0.0.5:8786' needs dask.distributed: "
                                        r"pip install 'dask\[distributed\]'"):
        sweep(CELLS, [0], SETUP, scheduler="tcp://10.0.0.5:8786")


def test_local_workers_are_cut_to_the_cores(monkeypatch):
    from ifslib.studies import sweep as module

    monkeypatch.setattr(module, "cores", lambda: 2)
    assert module._local_workers(2) == 2
    with pytest.warns(UserWarning, match="3 workers on 2 cores would oversubscribe them; using 2"):
        assert module._local_workers(3) == 2
    with pytest.raises(IFSError, match="workers"):
        module._local_workers(0)


def test_bad_cells_are_refused():
    with pytest.raises(IFSError, match="known strategies"):
        sweep([Cell("magic")], [0], SETUP, scheduler="serial")
    with pytest.raises(IFSError, match="unknown init"):
        sweep([Cell(init="random")], [0], SETUP, scheduler="serial")
    with pytest.raises(IFSError, match="unknown loss 'typo'; known losses: pixel"):
        sweep([Cell(loss="typo")], [0], SETUP, scheduler="serial")
    with pytest.raises(IFSError, match="at least one"):
        sweep([], [0], SETUP, scheduler="serial")


def test_rows_say_which_start_was_kept():
    # plain is one run of its seed's start; pyramid tries starts until one recovers (up to
    # Pyramid.n_starts) and the row names the one kept, so that a rate counts its trials honestly
    rows = sweep([Cell("plain"), Cell("pyramid")], [0, 1], SETUP, scheduler="serial")
    plain, pyramid = rows[:2], rows[2:]
    assert all((r["starts_tried"], r["start"]) == (1, 1) for r in plain)
    for r in pyramid:
        assert 1 <= r["start"] <= r["starts_tried"] <= 8
        if r["recovered"]:  # pyramid stops at the first start that passes the study's own test
            assert r["start"] == r["starts_tried"]
    assert any(r["starts_tried"] > 1 for r in pyramid), "4 steps a stage should not recover at once"
