"""``ifslib fit``'s options: names checked before the image is read or a search starts; an option the
automatic path uses only in part is said on standard error."""
from __future__ import annotations

import pytest

from ifslib.cli import _fit_options, build_parser, main


@pytest.mark.parametrize("option, said", [(["--loss", "typo"], "unknown loss 'typo'; known losses: pixel"),
                                          (["--strategy", "typo"], "unknown strategy 'typo'; known strategies: pyramid")])
def test_an_unknown_name_is_refused_before_the_image_is_read(option, said, tmp_path, capsys):
    # the image does not exist: the refusal names the option, so nothing was read (nor searched) before it
    code = main(["fit", str(tmp_path / "missing.png"), "--pattern", "auto", *option, "-o", str(tmp_path / "o.json")])
    err = capsys.readouterr().err
    assert code == 2 and said in err and "missing.png" not in err, err
    assert not (tmp_path / "o.json").exists()


def test_a_loss_named_for_the_automatic_path_is_said_on_standard_error(capsys):
    args = build_parser().parse_args(["fit", "koch", "--pattern", "auto", "--loss", "distance", "-o", "x.json"])
    assert _fit_options(args).loss == "distance"
    err = capsys.readouterr().err
    assert "--loss distance" in err and "fractal" in err and "multiscale_pixel" in err, err


def test_a_loss_named_for_a_pattern_is_used_without_a_word(capsys):
    args = build_parser().parse_args(["fit", "koch", "--pattern", "koch", "--loss", "distance", "-o", "x.json"])
    assert _fit_options(args).loss == "distance"
    assert capsys.readouterr().err == ""
