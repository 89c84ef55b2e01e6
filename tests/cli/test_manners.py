"""The command line's manners: ``--version``, exit codes in ``--help``, and progress that suits where it goes.

A fit whose standard error is a terminal draws live bars; redirected to a log it writes one line per
stage and no carriage-return redraws; its result stays on standard output.
"""
from __future__ import annotations

import io
import os
import subprocess
import sys

import pytest

import ifslib
from ifslib import progress
from ifslib.cli import EXIT_CODES, main


class _Terminal(io.StringIO):
    """A stream that says it is a terminal (what a console's standard error says)."""

    def isatty(self) -> bool:
        return True


def test_version(capsys):
    with pytest.raises(SystemExit) as stop:
        main(["--version"])
    assert stop.value.code == 0
    out = capsys.readouterr().out
    assert out.startswith(f"ifslib {ifslib.__version__} (torch "), out


def test_help_documents_the_exit_codes(capsys):
    with pytest.raises(SystemExit) as stop:
        main(["--help"])
    assert stop.value.code == 0
    out = capsys.readouterr().out
    assert "exit codes:" in out and "--version" in out
    for code in EXIT_CODES:
        assert f"  {code} " in out, f"--help does not explain exit code {code}"
    assert set(EXIT_CODES) == {0, 1, 2, 130}


def test_exit_codes(tmp_path, capsys):
    assert main(["render", "koch", "--size", "16", "--depth", "1", "-o", str(tmp_path / "k.png")]) == 0
    assert main(["info", str(tmp_path / "missing.json")]) == 2          # bad input: one line, no traceback
    assert capsys.readouterr().err.strip().startswith("ifslib info: error:")
    blocker = tmp_path / "a_file"
    blocker.write_text("")
    assert main(["render", "koch", "--size", "16", "--depth", "1", "-o", str(blocker / "k.png")]) == 1  # cannot write
    err = capsys.readouterr().err
    assert err.startswith("ifslib render: error:") and "Traceback" not in err
    with pytest.raises(SystemExit) as stop:
        main(["render", "--no-such-option"])
    assert stop.value.code == 2


def test_bars_only_on_a_terminal():
    assert progress.draw_bars(_Terminal()) is True
    assert progress.draw_bars(io.StringIO()) is False
    closed = io.StringIO()
    closed.close()
    assert progress.draw_bars(closed) is False


def test_a_run_draws_a_bar_on_a_terminal_and_one_line_in_a_log(monkeypatch):
    target = ifslib.load_target(ifslib.patterns.koch(depth=2), 32)
    start = ifslib.initialize(ifslib.patterns.koch(depth=2), target, jitter=0.05, seed=0)
    for stream, live in ((_Terminal(), True), (io.StringIO(), False)):
        monkeypatch.setattr(sys, "stderr", stream)
        ifslib.fit(start, target, steps=12, strategy="plain", progress=True)
        text = stream.getvalue()
        assert ("\r" in text) is live, repr(text)
        assert "fit · 32²: ran its 12 steps" in text if not live else "12/12" in text
        if not live:
            assert text.count("\n") == 1, repr(text)


@pytest.mark.slow
def test_a_fit_redirected_to_a_log_writes_one_line_per_stage(tmp_path):
    """The whole command in a subprocess, its standard error a file: no redraws, one line a stage."""
    png, out = tmp_path / "k.png", tmp_path / "fit.json"
    assert main(["render", "koch", "--size", "128", "--depth", "3", "-o", str(png)]) == 0
    env = {**os.environ, "IFSLIB_THREADS": os.environ.get("IFSLIB_THREADS", "2")}
    with open(tmp_path / "err.log", "w+") as log:
        proc = subprocess.run([sys.executable, "-m", "ifslib", "fit", str(png), "--size", "128", "--steps", "30",
                               "-o", str(out)], stdout=subprocess.PIPE, stderr=log, text=True, env=env, timeout=300)
        log.seek(0)
        err = log.read()
    assert proc.returncode == 0, err
    assert "\r" not in err, f"carriage-return redraws in a log: {err[:300]!r}"
    stages = [line for line in err.splitlines() if line.startswith("start ")]
    assert len(stages) >= 2 and all("steps" in line or "Chamfer" in line for line in stages), err  # 64², 128²
    assert len(err.splitlines()) <= 20, err
    assert proc.stdout.startswith(f"wrote {out}"), proc.stdout
