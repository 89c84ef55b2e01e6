"""``ifslib fit``'s options: names checked before the image is read or a search starts; an option the
automatic path uses only in part is said on standard error."""
from __future__ import annotations

import subprocess
import sys

import pytest

from ifslib.cli import _fit_options, build_parser, main


@pytest.mark.parametrize("option, said", [(["--loss", "typo"], "argument --loss: invalid choice: 'typo' (choose from 'pixel'"),
                                          (["--strategy", "typo"], "argument --strategy: invalid choice: 'typo' (choose from 'pyramid'")])
def test_an_unknown_name_is_refused_before_the_image_is_read(option, said, tmp_path, capsys):
    # the image does not exist: the refusal names the option, so nothing was read (nor searched) before it
    with pytest.raises(SystemExit) as exited:
        main(["fit", str(tmp_path / "missing.png"), "--pattern", "auto", *option, "-o", str(tmp_path / "o.json")])
    err = capsys.readouterr().err
    assert exited.value.code == 2 and said in err and "missing.png" not in err, err
    assert not (tmp_path / "o.json").exists()


def test_an_unknown_name_is_refused_before_torch_is_imported():
    # the names live in ifslib.names, which imports nothing: the command line checks them before the
    # library (and torch, a second's import) loads, so a misspelt option fails at once
    check = ("import sys\nfrom ifslib.cli import main\ntry:\n    main(['fit', 'x.png', '--loss', 'typo', '-o', 'y.json'])\n"
             "except SystemExit as e:\n    print(e.code, 'torch' in sys.modules)\n")
    done = subprocess.run([sys.executable, "-c", check], capture_output=True, text=True, check=True)
    assert done.stdout.split() == ["2", "False"], done.stdout + done.stderr


def test_the_names_the_command_line_offers_are_the_ones_the_library_runs():
    from ifslib.core.fitting.strategies import STRATEGIES
    from ifslib.core.scoring.losses import LOSSES

    actions = {a.dest: a for a in build_parser()._subparsers._group_actions[0].choices["fit"]._actions}
    assert tuple(actions["loss"].choices) == LOSSES and tuple(actions["strategy"].choices) == STRATEGIES


def test_a_loss_named_for_the_automatic_path_is_said_on_standard_error(capsys):
    args = build_parser().parse_args(["fit", "koch", "--pattern", "auto", "--loss", "distance", "-o", "x.json"])
    assert _fit_options(args).loss == "distance"
    err = capsys.readouterr().err
    assert "--loss distance" in err and "fractal" in err and "multiscale_pixel" in err, err


def test_a_loss_named_for_a_pattern_is_used_without_a_word(capsys):
    args = build_parser().parse_args(["fit", "koch", "--pattern", "koch", "--loss", "distance", "-o", "x.json"])
    assert _fit_options(args).loss == "distance"
    assert capsys.readouterr().err == ""
