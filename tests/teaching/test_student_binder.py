"""The students' Binder repository (``course/student_binder.py``): the student edition, the wheel and
``binder/``, with no solution line, no hidden test line and no truth of ``course/targets.py`` in any file.

The folder is written once for the module, from the real notebooks through nbgrader (marked
``grading``) with a stand-in wheel: the real wheel's contents are checked by test_exercises.py
(the package holds no answer key), and .ci/wheel.sh installs and runs the real one.
"""
import zipfile
from pathlib import Path

import nbformat
import pytest
from common_testing import load_module

ROOT = Path(__file__).resolve().parents[2]
binder = load_module("ifslib_student_binder", ROOT / "course" / "student_binder.py")
student = load_module("ifslib_student_edition", ROOT / "notebooks" / "student.py")
WHEEL = "ifslib-0.1.0-py3-none-any.whl"
INSTRUCTOR = sorted((ROOT / "notebooks").glob("*.ipynb"))


def stand_in_wheel(folder: Path) -> Path:
    """A wheel with the metadata `student_binder` reads (ifslib's name and its torch range)."""
    path = folder / WHEEL
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("ifslib-0.1.0.dist-info/METADATA", "Metadata-Version: 2.4\nName: ifslib\nVersion: 0.1.0\n"
                         "Requires-Dist: torch<3,>=2.0\nRequires-Dist: numpy>=1.24\n"
                         "Requires-Dist: dask[distributed]>=2024.1; extra == \"sweep\"\n")
        archive.writestr("ifslib/__init__.py", '"""ifslib."""\n')
    return path


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    out = tmp_path_factory.mktemp("student-binder") / "repo"
    files = binder.write(out, stand_in_wheel(tmp_path_factory.mktemp("wheel")))
    return out, files


def lines_of(path: Path) -> set[str]:
    """The stripped lines a file shows: a notebook's cells and stored outputs, a wheel's members, a text file."""
    if path.suffix == ".ipynb":
        book = nbformat.read(path, as_version=4)
        texts = [cell.source for cell in book.cells]
        for cell in book.cells:
            for output in cell.get("outputs", []):
                texts += [output.get("text", ""), output.get("evalue", ""), output.get("data", {}).get("text/plain", "")]
    elif path.suffix == ".whl":
        with zipfile.ZipFile(path) as archive:
            texts = [archive.read(name).decode(errors="replace") for name in archive.namelist()]
    else:
        texts = [path.read_text()]
    return {line.strip() for text in texts for line in "".join(text).splitlines() if line.strip()}


def secrets() -> set[str]:
    """Lines of the instructor's solutions and hidden tests that the instructor's edition shows nowhere else."""
    secret, shown = set(), set()
    for path in INSTRUCTOR:
        book = nbformat.read(path, as_version=4)
        secret |= student.solution_lines(book) | student.hidden_lines(book)
        for cell in book.cells:
            released = student.HIDDEN.sub("", student.student_source(cell.source))
            shown |= {line.strip() for line in released.splitlines() if line.strip()}
    return secret - shown


def truth_digits() -> dict[str, set[str]]:
    """Each truth of course/targets.py as the 5-decimal strings (truncated and rounded) of its maps and points.

    Round values (0.25, 0.12) are left out: they say nothing of the truth and occur everywhere.
    """
    targets = load_module("ifslib_course_targets", ROOT / "course" / "targets.py")
    digits = {}
    for name, truth in targets.TRUTHS.items():
        ifs = truth()
        values = ifs.maps().detach().double().flatten().tolist() + ifs.points.detach().double().flatten().tolist()
        digits[name] = {form for v in map(abs, values) if abs(v * 1e4 - round(v * 1e4)) > 1e-6
                        for form in (f"{int(v * 1e5) / 1e5:.5f}", f"{v:.5f}")}
    return digits


@pytest.mark.grading
def test_the_folder_holds_the_student_edition_the_wheel_and_binder_only(written):
    out, files = written
    names = {str(p.relative_to(out)) for p in files}
    notebooks = {p.name for p in INSTRUCTOR}
    assert names == notebooks | {WHEEL, "requirements-student.txt", "README.md", "binder/requirements.txt",
                                 "binder/runtime.txt"}
    assert (out / "binder" / "runtime.txt").read_text() == (ROOT / "binder" / "runtime.txt").read_text()
    for path in INSTRUCTOR:  # the release, not the instructor's file: no worked answer, no hidden test cell
        released = (out / path.name).read_text()
        assert "BEGIN SOLUTION" not in released and "BEGIN HIDDEN TESTS" not in released, path.name
    readme = (out / "README.md").read_text()
    assert "https://mybinder.org/v2/gh/<owner>/<repository>/main?urlpath=lab/tree/00_tutorial.ipynb" in readme
    assert "git push -u origin main" in readme and WHEEL in readme


@pytest.mark.grading
def test_the_binder_requirements_name_the_wheel_beside_them_and_nothing_outside_the_folder(written):
    out, _ = written
    lines = [line.strip() for line in (out / "binder" / "requirements.txt").read_text().splitlines()
             if line.strip() and not line.startswith("#")]
    assert lines[:2] == ["--extra-index-url https://download.pytorch.org/whl/cpu", "torch<3,>=2.0"]
    # repo2docker runs pip at the repository's root, where the wheel lies; the ./ makes it copy the
    # repository in first (a path without it is installed before the copy, and not found)
    assert f"./{WHEEL}" in lines and (out / WHEEL).is_file()
    assert lines[3:] == binder.student_packages() == ["jupyterlab>=4.0", "ipywidgets>=8.0", "ipykernel>=6.25"]
    assert not [line for line in lines if line.startswith(("-r", "-c", "-e", "..", "/"))]  # self-contained


@pytest.mark.grading
def test_no_solution_hidden_test_or_truth_is_in_any_file(written):
    out, files = written
    secret = secrets()
    assert len(secret) > 100  # the check has something to find: the course's answers and hidden tests
    leaked = {str(path.relative_to(out)): sorted(lines_of(path) & secret) for path in files}
    assert not any(leaked.values()), {k: v[:5] for k, v in leaked.items() if v}
    digits = truth_digits()
    instructor = "".join(path.read_text() for path in INSTRUCTOR)
    for name, forms in digits.items():  # the hidden tests hold each truth, so the check can see one
        assert any(form in instructor for form in forms), f"no digits of the {name} truth in notebooks/"
    texts = {str(p.relative_to(out)): "\n".join(lines_of(p)) for p in files}
    found = {(where, name, form) for where, text in texts.items() for name, forms in digits.items()
             for form in forms if form in text}
    assert not found, sorted(found)[:10]


def test_a_folder_with_other_files_is_refused_before_anything_is_removed(tmp_path):
    (tmp_path / ".git").mkdir()
    (tmp_path / "00_tutorial.ipynb").write_text("{}")
    (tmp_path / WHEEL).write_text("")
    (tmp_path / "binder").mkdir()
    binder.clear(tmp_path)  # what a previous run wrote goes; the clone's .git stays
    assert [p.name for p in tmp_path.iterdir()] == [".git"]
    (tmp_path / "00_tutorial.ipynb").write_text("{}")
    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(binder.BinderError, match="holds notes.txt, which this script did not write"):
        binder.clear(tmp_path)
    assert (tmp_path / "00_tutorial.ipynb").exists()


def test_a_file_that_is_not_an_ifslib_wheel_is_refused(tmp_path):
    other = tmp_path / "numpy-2.0-py3-none-any.whl"
    other.write_text("")
    with pytest.raises(binder.BinderError, match="not an ifslib wheel"):
        binder.write(tmp_path / "out", other)
    assert not (tmp_path / "out").exists()
    bare = tmp_path / WHEEL
    with zipfile.ZipFile(bare, "w") as archive:
        archive.writestr("ifslib/__init__.py", "")
    with pytest.raises(binder.BinderError, match="is not a wheel: it has 0 .dist-info/METADATA"):
        binder.requires(bare)
