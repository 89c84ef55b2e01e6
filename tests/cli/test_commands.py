"""``render``, ``fit`` and ``info`` end to end on a small Koch curve."""
import pytest

import ifslib
from ifslib.cli import main as cli


def test_cli_render_fit_info(tmp_path, capsys):
    png, spec, fitted = tmp_path / "k.png", tmp_path / "k.json", tmp_path / "fitted.json"
    ifslib.save_ifs(ifslib.patterns.koch(depth=2), spec)
    assert cli(["render", str(spec), "--size", "48", "-o", str(png)]) == 0
    assert cli(["fit", str(png), "--pattern", "koch", "--size", "48", "--depth", "2", "--steps", "5", "--quiet",
                "-o", str(fitted)]) == 0
    out = capsys.readouterr().out
    assert "IoU" in out and "(pyramid" in out  # the default strategy, and the steps it spent
    assert cli(["info", str(fitted)]) == 0
    out = capsys.readouterr().out
    assert "contraction" in out and "leaves at depth 2: 4^2 x 1 = 16" in out
    assert cli(["fit", str(tmp_path / "none.png"), "-o", str(fitted)]) == 2
    assert capsys.readouterr().err.strip().startswith("ifslib fit: error: no image file at")
    with pytest.raises(SystemExit):
        cli(["render"])
