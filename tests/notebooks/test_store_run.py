"""`run.py --preset teaching --into DIR` stores a notebook's run through store.py: its outputs kept, its bars
dropped, its teaching values recorded, the source notebook untouched."""
import json

import nbformat
import pytest

from test_notebook_runs import run  # notebooks/run.py, loaded once (store.py beside it on sys.path)

pytestmark = pytest.mark.notebook


def test_a_teaching_run_is_stored_with_its_values_and_without_its_bar(tmp_path, monkeypatch):
    book = nbformat.v4.new_notebook()
    book.cells = [nbformat.v4.new_code_cell("steps = 3", metadata={"tags": ["parameters"]}),
                  nbformat.v4.new_code_cell("import sys\nfrom tqdm import tqdm\n"
                                            "for _ in tqdm(range(steps), file=sys.stderr, disable=False):\n    pass\n"
                                            "print('ran', steps)")]
    book.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    source = tmp_path / "99_tiny.ipynb"
    nbformat.write(book, source)
    before = source.read_text()
    monkeypatch.setenv("IFSLIB_THREADS", "1")
    seconds = run.execute(source, "teaching", tmp_path / "out")
    stored = json.loads((tmp_path / "out" / source.name).read_text())
    assert seconds > 0 and source.read_text() == before
    recorded = stored["metadata"]["ifslib"]["stored"]
    assert isinstance(recorded.pop("seconds"), int)   # the run's time, what the first cell and the guide give
    assert recorded == {"preset": "teaching", "threads": 1, "parameters": {"steps": 3}}
    outputs = stored["cells"][1]["outputs"]
    assert ["".join(o["text"]) for o in outputs if o.get("name") == "stdout"] == ["ran 3\n"]
    assert not any(run_bar in "".join(o.get("text", "")) for o in outputs for run_bar in ("3/3", "100%"))
