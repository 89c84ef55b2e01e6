"""The notebooks as stored: the teaching run, executed top to bottom, at sizes that show the lesson.

What a reader sees (the notebook on GitHub or in JupyterLab, the book, the slides) is the stored
run, so it must be the run of the notebook's teaching values (its parameters cell), made by
``python notebooks/run.py`` (``make figures``), which records it in ``metadata["ifslib"]["stored"]``.
See docs/guide/teaching.md, "Stored outputs and CI".
"""
import json

import pytest

from test_notebook_runs import run  # notebooks/run.py, loaded once

NOTEBOOKS = run.notebooks()

#: The smallest ``size`` a stored run may be drawn at without a reason in ``metadata["ifslib"]["size_reason"]``.
MIN_SIZE = 128


def load(path):
    return json.loads(path.read_text())


def again(path) -> str:
    return f"store it again with python notebooks/run.py --only {path.stem}"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_stored_run_is_the_teaching_run(path):
    stored = load(path)["metadata"].get("ifslib", {}).get("stored")
    assert stored, f"{path.name}: no stored run is recorded in metadata['ifslib']['stored']; {again(path)}"
    assert stored.get("preset") == "teaching", f"{path.name}: stored a {stored.get('preset')!r} run; {again(path)}"
    assert isinstance(stored.get("threads"), int), f"{path.name}: the stored run's thread count is not recorded"
    now = run.teaching_parameters(path)
    changed = {k for k in now.keys() | stored.get("parameters", {}).keys() if now.get(k) != stored["parameters"].get(k)}
    assert not changed, f"{path.name}: {sorted(changed)} changed since the run was stored; {again(path)}"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_stored_top_to_bottom_in_a_fresh_kernel_without_error(path):
    book = load(path)
    assert book["metadata"]["kernelspec"]["name"] == "python3"
    code = [c for c in book["cells"] if c["cell_type"] == "code"]
    counts = [c["execution_count"] for c in code]
    assert counts == list(range(1, len(code) + 1)), f"{path.name}: not run top to bottom in a fresh kernel; {again(path)}"
    errors = [k for k, c in enumerate(book["cells"]) for o in c.get("outputs", []) if o["output_type"] == "error"]
    assert not errors, f"{path.name}: cells {errors} stored an error"
    assert any("image/png" in o.get("data", {}) for c in code for o in c["outputs"]), f"{path.name}: no picture stored"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_no_stored_picture_below_128_px_without_a_reason(path):
    size = run.teaching_parameters(path).get("size")
    reason = load(path)["metadata"].get("ifslib", {}).get("size_reason", "")
    if size is not None and size < MIN_SIZE:
        assert isinstance(reason, str) and len(reason) > 20, (
            f"{path.name}: its pictures are stored at {size}² (under {MIN_SIZE}): raise its teaching size, or say "
            "why in metadata['ifslib']['size_reason']")


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_no_cell_keeps_the_timestamps_of_another_run(path):
    # store.py executes without timing; a timestamp left by an editor or an older run would date
    # cells of the stored run wrongly (and a reader would add them up to the notebook's run time)
    stamped = [k for k, c in enumerate(load(path)["cells"]) if "execution" in c.get("metadata", {})]
    assert not stamped, f"{path.name}: cells {stamped} keep metadata['execution'] timestamps; {again(path)}"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_no_cell_hides_its_result_with_a_trailing_semicolon(path):
    # make test-stored runs the stored notebooks under nbval, whose kernel executes without storing
    # history; IPython then reads the ';' of the cell run before, not this one's, so `fig.colorbar(...);`
    # shows `<matplotlib.colorbar.Colorbar at 0x...>` there and nothing in the stored run. `_ = ...`
    # hides a result under both.
    from IPython.core.displayhook import DisplayHook

    cells = [k for k, c in enumerate(load(path)["cells"]) if c["cell_type"] == "code"
             and DisplayHook.semicolon_at_end_of_expression("".join(c["source"]))]
    assert not cells, f"{path.name}: cells {cells} end with ';' to hide a result; assign it instead (`_ = ...`)"
