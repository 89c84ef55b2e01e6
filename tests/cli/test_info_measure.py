"""``ifslib info`` prints the probabilities (the file's or the default) and the similarity dimension."""
import math

import ifslib
from ifslib.cli import main


def test_info_on_a_similarity_pattern(capsys):
    assert main(["info", "carpet"]) == 0
    out = capsys.readouterr().out
    assert "probabilities (default: in proportion to |det|, with a floor): " + ", ".join(["0.1250"] * 8) in out
    assert f"similarity dimension (Moran's equation): {math.log(8) / math.log(3):.4f}" in out


def test_info_on_a_file_with_probabilities(tmp_path, capsys):
    fern = ifslib.patterns.fern()
    fern.probabilities = (0.01, 0.85, 0.07, 0.07)
    path = ifslib.save_ifs(fern, tmp_path / "fern.json")
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    assert "probabilities (the file's): 0.0100, 0.8500, 0.0700, 0.0700" in out
    assert "not defined, the maps are not similarities" in out and "an upper bound of the box dimension" in out
