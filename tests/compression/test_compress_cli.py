"""``ifslib compress`` and ``ifslib decompress``: round trips, exit codes and one-line errors."""
import numpy as np
import pytest
from PIL import Image

from ifslib.cli import main
from compression_images import photo


@pytest.fixture
def png(tmp_path):
    path = tmp_path / "photo.png"
    Image.fromarray((photo(48).numpy() * 255).round().astype(np.uint8)).convert("RGB").save(path)
    return path


@pytest.mark.parametrize("method", ["collage", "attractor"])
def test_compress_then_decompress(tmp_path, png, capsys, method):
    packed, out = tmp_path / "photo.ifsc", tmp_path / "out.png"
    assert main(["compress", str(png), "-o", str(packed), "--bpp", "1.0", "--method", method, "--quiet"]) == 0
    said = capsys.readouterr().out
    assert packed.stat().st_size * 8 <= 48 * 48 and "decoded PSNR" in said and method in said
    assert main(["decompress", str(packed), "-o", str(out), "--scale", "2"]) == 0
    assert Image.open(out).size == (96, 96)
    decoded = np.asarray(Image.open(out).resize((48, 48), Image.BOX), dtype=float) / 255
    assert np.abs(decoded - np.asarray(Image.open(png).convert("L"), dtype=float) / 255).mean() < 0.08


def test_quality_instead_of_a_rate(tmp_path, png):
    assert main(["compress", str(png), "-o", str(tmp_path / "q.ifsc"), "--quality", "28", "--method", "collage"]) == 0


@pytest.mark.parametrize("argv, words", [
    (["compress", "MISSING.png", "-o", "x.ifsc", "--bpp", "1"], "no image file"),
    (["decompress", "PNG", "-o", "x.png"], "IFSC"),
    (["decompress", "MISSING.ifsc", "-o", "x.png"], "no compressed file"),
    (["compress", "PNG", "-o", "x.ifsc", "--bpp", "0.001"], "too few"),
])
def test_bad_input_is_one_line_and_exit_2(tmp_path, png, capsys, argv, words):
    argv = [str(png) if a == "PNG" else str(tmp_path / a) if a.startswith(("MISSING", "x.")) else a for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and "\n" not in err and err.startswith(f"ifslib {argv[0]}: error:")


@pytest.mark.parametrize("argv", [["compress", "a.png", "-o", "b"], ["compress", "a.png", "-o", "b", "--bpp", "-1"],
                                  ["decompress", "a", "-o", "b", "--scale", "x"]])
def test_bad_arguments_exit_2(argv):
    with pytest.raises(SystemExit) as stop:
        main(argv)
    assert stop.value.code == 2


def test_help_names_the_subcommands(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    assert "compress" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        main(["compress", "--help"])
    assert "--method {collage,attractor}" in capsys.readouterr().out
