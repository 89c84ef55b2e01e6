"""course/grading.py from the command line, as an instructor runs it: with the paper's images out of reach it
refuses before it lays out or grades anything, and says how to provide them (issue 63)."""
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_grading_refuses_when_the_papers_images_cannot_be_found(tmp_path):
    empty = tmp_path / "empty"
    empty.mkdir()
    env = dict(os.environ, IFSLIB_DATA=str(empty), IFSLIB_CACHE=str(empty),
               IFSLIB_DATA_URL=(tmp_path / "nowhere").as_uri())  # no download either
    course = tmp_path / "course"
    done = subprocess.run([sys.executable, str(ROOT / "course" / "grading.py"), str(course), "--check"],
                          capture_output=True, text=True, env=env, cwd=tmp_path, timeout=120)
    assert done.returncode != 0
    message = done.stderr
    assert "koch.png, sierpinski.png, apple.png, flower.png" in message, message
    assert "Set IFSLIB_DATA" in message and "docs/guide/course.md#grading" in message, message
    assert "Traceback" not in message, message
    assert not course.exists(), "nothing may be laid out before the images are found"
