"""Every numeric option of ``render``, ``fit`` and ``info`` at 0, negative, NaN, inf and huge values.

Each either works or exits with status 2 and one ``error:`` line naming the option's value (argparse's
own refusals add its usage line), never a traceback; a size or a depth too large for memory is refused
before anything is allocated.
"""
from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

import ifslib
from ifslib.cli import main


def _run(argv: list[str], capsys) -> tuple[int, str]:
    """``main(argv)``'s exit status (argparse's exits included) and its standard error."""
    try:
        code = main(argv)
    except SystemExit as stop:
        code = stop.code
    return code, capsys.readouterr().err


@pytest.fixture(scope="module")
def png(tmp_path_factory):
    path = tmp_path_factory.mktemp("numbers") / "koch.png"
    assert main(["render", "koch", "--size", "32", "--depth", "2", "-o", str(path)]) == 0
    return path


RENDER = ["render", "koch", "--size", "16", "--depth", "1"]
ATTRACTOR = ["render", "koch", "--size", "16", "--depth", "attractor"]
CHAOS = ["render", "koch", "--size", "16", "--chaos", "200"]
HUGE = "100000000"

# (arguments, what standard error says)
REFUSED = [
    (["render", "koch", "--size", "0"], "size must be an integer >= 1"),
    (["render", "koch", "--size", "-1"], "size must be an integer >= 1"),
    (["render", "koch", "--size", "nan"], "argument --size: invalid int value"),
    (["render", "koch", "--size", HUGE, "--depth", "1"], "over the memory budget"),
    (["render", "koch", "--size", "0", "--chaos", "200"], "size must be an integer >= 1"),
    (["render", "koch", "--size", HUGE, "--chaos", "200"], "over the memory budget"),
    (["render", "koch", "--size", HUGE, "--depth", "attractor"], "needs more than"),
    (RENDER[:-1] + ["-1"], "depth must be an integer >= 0"),
    (RENDER[:-1] + ["inf"], "argument --depth: expected an integer or 'attractor'"),
    (RENDER[:-1] + ["1000"], "4^1000 = about 10^602.1 leaf maps, far over the memory budget"),
    (RENDER[:-1] + ["1000000000"], "far over the memory budget"),
    (ATTRACTOR + ["--tolerance", "0"], "tolerance must be a finite number of pixels > 0"),
    (ATTRACTOR + ["--tolerance", "-1"], "tolerance must be a finite number of pixels > 0"),
    (ATTRACTOR + ["--tolerance", "nan"], "tolerance must be a finite number of pixels > 0"),
    (ATTRACTOR + ["--tolerance", "inf"], "tolerance must be a finite number of pixels > 0"),
    (ATTRACTOR + ["--tolerance", "1e-300"], "needs more than 4,000,000 leaves"),
    (CHAOS[:-1] + ["0"], "the number of chaos-game points must be an integer >= 1"),
    (CHAOS[:-1] + ["-1"], "the number of chaos-game points must be an integer >= 1"),
    (CHAOS[:-1] + ["1e9"], "argument --chaos: invalid int value"),
    (CHAOS[:-1] + ["100000000000"], "over the memory budget"),
    (CHAOS + ["--seed", "-1"], "seed must be an integer >= 0"),
    (RENDER + ["--sigma", "0"], "sigma must be a finite number > 0"),
    (RENDER + ["--sigma", "-1"], "sigma must be a finite number > 0"),
    (RENDER + ["--sigma", "nan"], "sigma must be a finite number > 0"),
    (RENDER + ["--sigma", "inf"], "sigma must be a finite number > 0"),
    (RENDER + ["--sigma", "1e300"], "sigma must be from"),
    (RENDER + ["--sigma", "1e-300"], "sigma must be from"),
    (["render", "koch", "--size", "16", "--window", "nan", "0", "0.5", "0.5"], "window must be finite"),
    (["render", "koch", "--size", "16", "--window", "inf", "0", "0.5", "0.5"], "window must be finite"),
    (["render", "koch", "--size", "16", "--window", "0", "0", "0", "0.5"], "has zero or negative size"),
    (RENDER + ["--window", "0", "0", "0.5", "0.5"], "--window draws the attractor: leave out --depth"),
    (["info", "koch", "--depth", "-1"], "depth must be an integer >= 0"),
    (["info", "koch", "--depth", "nan"], "argument --depth: invalid int value"),
]

FIT = ["--size", "16", "--steps", "1", "--strategy", "plain"]
FIT_REFUSED = [
    (["--size", "0"], "size must be an integer >= 1"),
    (["--size", "-1"], "size must be an integer >= 1"),
    (["--size", "inf"], "argument --size: invalid int value"),
    (["--size", HUGE], "target needs about 5.96e+08 GiB, over the memory budget"),
    (["--depth", "-1"], "depth must be an integer >= 0"),
    (["--depth", "1000"], "far over the memory budget"),
    (["--steps", "-1"], "steps must be an integer >= 0"),
    (["--steps", "nan"], "argument --steps: invalid int value"),
    (["--tol", "-1"], "tol must be None or a finite number >= 0"),
    (["--tol", "nan"], "tol must be None or a finite number >= 0"),
    (["--tol", "inf"], "tol must be None or a finite number >= 0"),
    (["--lr", "0"], "lr must be a finite number > 0 and at most 1"),
    (["--lr", "-1"], "lr must be a finite number > 0 and at most 1"),
    (["--lr", "nan"], "lr must be a finite number > 0 and at most 1"),
    (["--lr", "inf"], "lr must be a finite number > 0 and at most 1"),
    (["--lr", "1e300"], "lr must be a finite number > 0 and at most 1"),
    (["--jitter", "-1"], "jitter must be a number from 0 to 1"),
    (["--jitter", "nan"], "jitter must be a number from 0 to 1"),
    (["--jitter", "inf"], "jitter must be a number from 0 to 1"),
    (["--jitter", "1e300"], "jitter must be a number from 0 to 1"),
    (["--seed", "-1"], "seed must be an integer >= 0"),
    (["--seed", "100000000000000000000"], "seed must be an integer from 0 to 9,223,372,036,854,775,807"),
    (["--pattern", "auto", "--maps", "0"], "number of maps must be an integer >= 2"),
    (["--pattern", "auto", "--maps", "-1"], "number of maps must be an integer >= 2"),
    (["--pattern", "auto", "--maps", "1000"], "number of maps must be at most 64"),
    (["--pattern", "auto", "--size", HUGE], "over the memory budget"),
]


def _refused(code: int, err: str, said: str) -> None:
    assert code == 2, err
    assert said in err, err
    assert "Traceback" not in err
    lines = [line for line in err.splitlines() if line.strip()]
    assert sum("error:" in line for line in lines) == 1 and said in lines[-1], err
    if "invalid" in said or "expected" in said:  # argparse: its usage, then one error line
        assert lines[0].startswith("usage:") and lines[-1].startswith("python -m ifslib "), err
    else:
        assert len(lines) == 1 and lines[0].startswith("ifslib ") and ": error: " in lines[0], err


@pytest.mark.parametrize("argv, said", REFUSED, ids=[" ".join(a[2:] if a[0] == "render" else a) for a, _ in REFUSED])
def test_render_and_info_refuse_bad_numbers(argv, said, tmp_path, capsys):
    out = [] if argv[0] == "info" else ["-o", str(tmp_path / "out.png")]
    _refused(*_run(argv + out, capsys), said)
    assert not (tmp_path / "out.png").exists()


@pytest.mark.parametrize("options, said", FIT_REFUSED, ids=[" ".join(o) for o, _ in FIT_REFUSED])
def test_fit_refuses_bad_numbers(options, said, png, tmp_path, capsys):
    _refused(*_run(["fit", str(png), *FIT, *options, "--quiet", "-o", str(tmp_path / "out.json")], capsys), said)
    assert not (tmp_path / "out.json").exists()


def _image(path) -> np.ndarray:
    return np.asarray(Image.open(path), dtype=np.uint8)


def test_render_extremes_that_work(tmp_path, capsys):
    out = str(tmp_path / "out.png")
    assert main(RENDER + ["--sigma", "1000", "-o", out]) == 0  # the widest line: white everywhere
    assert (_image(out) == 255).all()
    # the narrowest line: the inside of the carpet's boxes alone, no NaN on the figure
    assert main(["render", "carpet", "--size", "16", "--depth", "1", "--sigma", "1e-12", "-o", out]) == 0
    narrow = _image(out)
    assert set(np.unique(narrow)) == {0, 255} and (narrow == 255).sum() == 128
    assert main(["render", "koch", "--size", "1", "--depth", "1", "-o", out]) == 0 and _image(out).shape == (1, 1)
    assert main(RENDER[:-1] + ["0", "-o", out]) == 0
    assert main(ATTRACTOR + ["--tolerance", "1e300", "-o", out]) == 0
    assert main(CHAOS + ["--seed", "100000000000000000000", "-o", out]) == 0  # numpy takes any seed >= 0
    assert main(["render", "koch", "--size", "16", "--window", "-1", "-1", "1", "1", "-o", out]) == 0
    assert "Traceback" not in capsys.readouterr().err


def test_info_prints_an_astronomical_leaf_count(capsys):
    for depth, count in [("0", "4^0 x 1 = 1 leaves"), ("1000", "4^1000 x 1 = about 10^602.1 leaves"),
                         ("1000000000", "4^1000000000 x 1 = about 10^602059991.3 leaves")]:
        assert main(["info", "koch", "--depth", depth]) == 0
        assert capsys.readouterr().out.splitlines()[-1] == f"leaves at depth {depth}: {count}"


def test_fit_extremes_that_work(png, tmp_path, capsys):
    out = tmp_path / "out.json"
    for options in (["--steps", "0"], ["--depth", "0"], ["--tol", "0"], ["--tol", "1e300"], ["--lr", "1"],
                    ["--lr", "1e-300"], ["--jitter", "0"], ["--jitter", "0.01"], ["--seed", str(2**63 - 1)]):
        assert main(["fit", str(png), *FIT, *options, "--quiet", "-o", str(out)]) == 0, options
        assert ifslib.load_ifs(out).meta["target"]["inverted"] is False
    assert "Traceback" not in capsys.readouterr().err
