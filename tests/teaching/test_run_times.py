"""Each notebook's run time has one source: the stored run's ``metadata["ifslib"]["stored"]["seconds"]``.

`notebooks/store.py` records it when ``make figures`` stores a notebook's teaching run; the
notebook's first cell ("**How long it runs**: 7 min 18 s at the teaching values ...") and the
teaching column of the table in docs/guide/teaching.md (which docs/guide/course.md includes) must
give that time, to the second they are written in. After storing a notebook again, write the
time this test asks for in both.
"""
import json
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
GUIDE = ROOT / "docs" / "guide" / "teaching.md"
BOOKS = sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb"))


def stored_seconds(path):
    return json.loads(path.read_text())["metadata"]["ifslib"]["stored"].get("seconds")


def as_text(seconds):
    """7 min 18 s, 44 s: how the first cells and the guide write a time."""
    minutes, rest = divmod(int(seconds), 60)
    return f"{minutes} min {rest} s" if minutes else f"{rest} s"


def seconds_of(text):
    match = re.fullmatch(r"(?:(\d+) min)?\s*(?:(\d+) s)?", text.strip())
    assert match and any(match.groups()), f"not a time: {text!r}"
    return 60 * int(match.group(1) or 0) + int(match.group(2) or 0)


def first_cell_time(path):
    source = "".join(json.loads(path.read_text())["cells"][0]["source"])
    match = re.search(r"\*\*How long it runs\*\*:\s*(?:about\s+)?(.*?) at the teaching values", source, flags=re.S)
    return match.group(1) if match else None


def guide_times():
    """{notebook stem: its teaching time as the guide's table writes it}."""
    row = r"^\|[^|\n]*\|\s*\[[^\]]*\]\(\.\./\.\./notebooks/(\w+)\.ipynb\)(?:\s*\|[^|\n]*){3}\|\s*([^|\n]*?)\s*\|\s*$"
    return dict(re.findall(row, GUIDE.read_text(), flags=re.M))


def test_as_text_and_back():
    assert as_text(438) == "7 min 18 s" and as_text(44) == "44 s" and as_text(60) == "1 min 0 s"
    assert all(seconds_of(as_text(s)) == s for s in (4, 59, 60, 96, 438))


@pytest.mark.parametrize("path", BOOKS, ids=lambda p: p.stem)
def test_the_first_cell_gives_the_stored_runs_time(path):
    seconds = stored_seconds(path)
    assert isinstance(seconds, int), f"{path.name}: no time recorded in metadata['ifslib']['stored']['seconds']"
    written = first_cell_time(path)
    assert written, f"{path.name}: its first cell has no '**How long it runs**: ... at the teaching values'"
    assert abs(seconds_of(written) - seconds) <= 1, (
        f"{path.name}: the first cell says {written}, the stored run took {as_text(seconds)}")


def test_the_guides_table_gives_the_stored_runs_times():
    table = guide_times()
    assert set(table) == {p.stem for p in BOOKS}, f"the table's notebooks: {sorted(table)}"
    wrong = {stem: (written, as_text(stored_seconds(ROOT / "notebooks" / f"{stem}.ipynb")))
             for stem, written in table.items()
             if abs(seconds_of(written) - stored_seconds(ROOT / "notebooks" / f"{stem}.ipynb")) > 1}
    assert not wrong, f"docs/guide/teaching.md's teaching column (written, stored): {wrong}"
