"""A notebook run without the paper's images (no ``IFSLIB_DATA``, no download) says what is missing.

The explorer used to swallow the missing file into a widget warning, and a later cell failed with a
``KeyError``; now its first cell that needs an image says which one is missing and how to get it,
and the notebook runs on without a target.
"""
from __future__ import annotations

import json
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.slow
def test_explorer_notebook_without_the_papers_images(tmp_path, monkeypatch):
    papermill = pytest.importorskip("papermill")
    monkeypatch.delenv("IFSLIB_DATA", raising=False)           # the kernel inherits this environment
    monkeypatch.setenv("IFSLIB_CACHE", str(tmp_path / "empty-cache"))
    monkeypatch.setenv("IFSLIB_DATA_URL", "http://127.0.0.1:9/")  # no network: the download fails at once
    out = tmp_path / "00_explore.ipynb"
    papermill.execute_notebook(str(ROOT / "notebooks" / "00_explore.ipynb"), str(out), cwd=str(tmp_path),
                               kernel_name="python3", progress_bar=False)   # raises on any cell's error
    code = [c for c in json.loads(out.read_text())["cells"] if c["cell_type"] == "code"]
    texts = ["".join("".join(o.get("text", "")) for o in c["outputs"] if o["output_type"] == "stream") for c in code]
    first = next(i for i, c in enumerate(code) if "Explorer(" in "".join(c["source"]))
    assert "No target image" in texts[first] and "koch.png" in texts[first] and "IFSLIB_DATA" in texts[first], texts
    assert not any("No target image" in t for t in texts[:first])
