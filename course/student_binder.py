"""Write the students' Binder repository: ``python course/student_binder.py OUT [--wheel PATH]``.

The repository's own ``binder/`` builds the whole repository, so a Binder of it serves the
instructor's edition (``notebooks/``: worked answers, hidden tests) and ``course/targets.py`` (the
truths of the fit exercises): it is the instructor's. This writes the students' one, a
self-contained folder to push as a repository of its own (its README says how)::

    OUT/
      README.md                        how to publish it, the Binder address, what students do
      *.ipynb                          the student edition (nbgrader's release: notebooks/student.py)
      ifslib-<version>-py3-none-any.whl the wheel, built here (pip wheel --no-deps) or given (--wheel)
      requirements-student.txt         JupyterLab and widgets, for a student installing on their own computer
      binder/requirements.txt          torch from PyTorch's CPU index, the wheel by relative path, JupyterLab and widgets
      binder/runtime.txt               Python's version, the same as the instructor's binder/

Nothing of ``notebooks/`` nor ``course/`` is copied. ``OUT`` may be a clone of that repository:
what a previous run wrote is replaced and ``.git`` is kept; any other file in it is refused. The
folder is also what a student downloads to install on their own computer (start-here's pip
commands run in it). Needs nbgrader (``make setup-grading``), as ``make student`` does.

    python course/student_binder.py build/student-binder      # make student-binder
"""
from __future__ import annotations

import argparse
import re
import shutil
import subprocess
import sys
import tempfile
import zipfile
from email.parser import Parser
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from scripts import ROOT, load_script  # noqa: E402

STUDENT_REQUIREMENTS = ROOT / "requirements-student.txt"
RUNTIME = ROOT / "binder" / "runtime.txt"
#: PyTorch's index of CPU wheels: an extra index, since it lacks JupyterLab; its ``+cpu`` wheels rank
#: above PyPI's CUDA build of the same version, several GB that these notebooks never use.
TORCH_INDEX = "https://download.pytorch.org/whl/cpu"
#: A clone of the published repository keeps these; any other name not written here is refused.
KEPT = {".git"}


class BinderError(RuntimeError):
    """A folder or a wheel the student repository cannot be written from."""


def _student_module():
    """``notebooks/student.py``, which writes the student edition through nbgrader."""
    return load_script("notebooks/student.py", "ifslib_student_edition")


def is_written_here(path: Path) -> bool:
    """Whether ``path`` (an entry of OUT) is one this script writes, and may replace."""
    return (path.name in {"README.md", "requirements-student.txt", "binder"} or path.suffix == ".ipynb"
            or (path.name.startswith("ifslib-") and path.suffix == ".whl"))


def clear(out: Path) -> None:
    """Remove what a previous run wrote in ``out``; raise `BinderError` naming any other entry, before removing any."""
    if not out.exists():
        return
    if not out.is_dir():
        raise BinderError(f"{out} is a file, not a folder")
    entries = sorted(out.iterdir())
    strangers = [p.name for p in entries if p.name not in KEPT and not is_written_here(p)]
    if strangers:
        raise BinderError(f"{out} holds {', '.join(strangers)}, which this script did not write: give an empty "
                          "folder, a new one, or a clone of the student repository")
    for path in entries:
        if path.name not in KEPT:
            shutil.rmtree(path) if path.is_dir() else path.unlink()


def build_wheel(folder: Path) -> Path:
    """``pip wheel --no-deps`` of the repository into ``folder``; the wheel's path."""
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", "-w", str(folder), str(ROOT)],
                   check=True)
    wheels = sorted(folder.glob("ifslib-*.whl"))
    if len(wheels) != 1:
        raise BinderError(f"pip wheel wrote {[w.name for w in wheels]} in {folder}, not one ifslib wheel")
    return wheels[0]


def requires(wheel: Path) -> list[str]:
    """The ``Requires-Dist`` lines of ``wheel``'s metadata (its dependencies, extras' ones included)."""
    with zipfile.ZipFile(wheel) as archive:
        names = [n for n in archive.namelist() if n.endswith(".dist-info/METADATA")]
        if len(names) != 1:
            raise BinderError(f"{wheel.name} is not a wheel: it has {len(names)} .dist-info/METADATA files")
        metadata = Parser().parsestr(archive.read(names[0]).decode())
    return metadata.get_all("Requires-Dist") or []


def torch_requirement(wheel: Path) -> str:
    """The wheel's own torch range (``torch<3,>=2.0``), so that Binder installs a torch ifslib accepts."""
    found = [r.replace(" ", "") for r in requires(wheel) if re.match(r"torch\s*[<>=!~(]", r) and ";" not in r]
    if len(found) != 1:
        raise BinderError(f"{wheel.name} names torch {len(found)} times among its requirements, not once")
    return found[0]


def student_packages() -> list[str]:
    """The requirements of ``requirements-student.txt``, its comments left out."""
    lines = (line.split("#", 1)[0].strip() for line in STUDENT_REQUIREMENTS.read_text().splitlines())
    return [line for line in lines if line]


def binder_requirements(wheel_name: str, torch: str) -> str:
    """``binder/requirements.txt``: torch's CPU wheel, the wheel beside the notebooks, the student packages."""
    return "\n".join([
        "# Binder (repo2docker) for the student edition, written by ifslib's course/student_binder.py.",
        "# torch from PyTorch's CPU index (its +cpu wheels rank above PyPI's CUDA build of the same version).",
        f"--extra-index-url {TORCH_INDEX}",
        torch,
        "# ifslib from its wheel at the repository's root: repo2docker runs pip there, and a path starting",
        "# with . makes it copy the repository in before installing (without it pip runs before the copy)",
        f"./{wheel_name}",
        "# JupyterLab, ipywidgets and ipykernel, as requirements-student.txt",
        *student_packages(),
        "",
    ])


README = """# Differentiable IFS: the student edition

The notebooks of the course without their answers (nbgrader's release: each exercise's answer
cell is `...  # YOUR CODE HERE`, the graders' hidden tests are out), the `ifslib` wheel
(`{wheel}`) and a Binder recipe (`binder/`). Written by `make student-binder`
(`course/student_binder.py`) in ifslib's repository at commit {commit}; write it again after
each change of the notebooks or of ifslib.

## For the instructor: publish it

Binder builds public repositories only. Push this folder as a repository of its own, never as a
branch of the course's repository: a public course repository shows the answers on its main
branch.

```bash
cd {out}
git init -b main
git add -A
git commit -m "Student edition at ifslib {commit}"
git remote add origin https://github.com/<owner>/<repository>.git
git push -u origin main
```

After the next `make student-binder` into the same clone (the script keeps `.git`), `git add -A`,
commit and push again. The address to give the students:

    https://mybinder.org/v2/gh/<owner>/<repository>/main?urlpath=lab/tree/00_tutorial.ipynb

The first launch of a commit builds its image (several minutes: torch's CPU wheel and
JupyterLab); the next ones start in about a minute. On a JupyterHub, install the image with
`pip install -r binder/requirements.txt` from this folder's root.

## For students

Open the Binder address your instructor gives you: JupyterLab opens on the tutorial, with
nothing to install. Binder deletes your copy when you close it or after about ten minutes idle:
download your notebooks (right click, Download) before you leave.

To work on your own computer instead (Python 3.10 or newer), download this folder and run, in it
(torch from PyTorch's index of CPU wheels: a plain `pip install torch` on Linux fetches the CUDA
build, several GB these notebooks never use):

```bash
python3 -m venv ifs-course && . ifs-course/bin/activate
pip install torch --index-url https://download.pytorch.org/whl/cpu
pip install {wheel} -r requirements-student.txt
jupyter lab 00_tutorial.ipynb
```

On Windows, in PowerShell (the environment's Python by its path: no activation, which the
execution policy often blocks):

```powershell
py -m venv ifs-course
ifs-course\\Scripts\\python -m pip install torch --index-url https://download.pytorch.org/whl/cpu
ifs-course\\Scripts\\python -m pip install {wheel} -r requirements-student.txt
ifs-course\\Scripts\\python -m jupyter lab 00_tutorial.ipynb
```

The course's "Start here" page has these steps in full, and Google Colab's.

The notebooks that fit the paper's images (`koch`, `sierpinski`, `apple`, `flower`) download them
from the paper's repository (github.com/cory-b-scott/diff_ifs) on first use.
"""


def commit() -> str:
    """The repository's short commit, with ``+changes`` when its files differ from it; ``unknown`` without git."""
    try:
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True,
                              check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=ROOT,
                               capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return head + ("+changes" if dirty else "")


def write(out: Path, wheel: Path | None = None, source: Path | None = None) -> list[Path]:
    """Write the student repository into ``out``; returns the files written.

    Parameters
    ----------
    out : Path
        The folder: new, empty, or one this script wrote (a clone of the student repository).
    wheel : Path, optional
        An ifslib wheel already built; None builds one from the repository.
    source : Path, optional
        The instructor's notebooks; ``notebooks/`` when None.

    Raises
    ------
    BinderError
        For an ``out`` holding other files, or a wheel that is not ifslib's.
    """
    student = _student_module()
    source = student.NOTEBOOKS if source is None else source
    if wheel is not None and not (wheel.is_file() and wheel.name.startswith("ifslib-") and wheel.suffix == ".whl"):
        raise BinderError(f"{wheel} is not an ifslib wheel file (ifslib-<version>-py3-none-any.whl)")
    clear(out)
    out.mkdir(parents=True, exist_ok=True)
    student.write_edition(out, source)
    with tempfile.TemporaryDirectory(prefix="ifslib-wheel-") as folder:
        built = build_wheel(Path(folder)) if wheel is None else wheel
        torch = torch_requirement(built)
        shutil.copy2(built, out / built.name)
    wheel_name = built.name
    shutil.copy2(STUDENT_REQUIREMENTS, out / STUDENT_REQUIREMENTS.name)
    (out / "binder").mkdir()
    (out / "binder" / "requirements.txt").write_text(binder_requirements(wheel_name, torch))
    shutil.copy2(RUNTIME, out / "binder" / "runtime.txt")
    (out / "README.md").write_text(README.format(wheel=wheel_name, commit=commit(), out=out))
    return sorted(p for p in out.rglob("*") if p.is_file() and ".git" not in p.relative_to(out).parts)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path, help="the folder to write (new, empty, or one this script wrote)")
    parser.add_argument("--wheel", type=Path, help="an ifslib wheel already built (default: build one)")
    args = parser.parse_args(argv)
    try:
        files = write(args.out, args.wheel)
    except BinderError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    print(f"student Binder repository in {args.out}: {len(files)} files "
          f"({sum(p.suffix == '.ipynb' for p in files)} notebooks, the wheel, binder/); its README says how to publish it")
    return 0


if __name__ == "__main__":
    sys.exit(main())
