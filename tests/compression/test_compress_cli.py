"""``ifslib compress`` and ``ifslib decompress``: round trips, exit codes and one-line errors."""
import numpy as np
import pytest
from PIL import Image

from ifslib.cli import main
from ifslib.cli_compress import read_gray
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


@pytest.mark.slow
def test_an_hv_partition_from_the_command_line(tmp_path, png, capsys):
    from ifslib.compression import read
    from ifslib.compression.config import PARTITIONS

    packed, out = tmp_path / "hv.ifsc", tmp_path / "hv.png"
    assert main(["compress", str(png), "-o", str(packed), "--bpp", "1.0", "--partition", "hv", "--quiet"]) == 0
    assert read(packed).options.partition == "hv" and packed.stat().st_size * 8 <= 48 * 48
    assert main(["decompress", str(packed), "-o", str(out)]) == 0 and Image.open(out).size == (48, 48)
    from ifslib.cli import build_parser

    choices = next(a for a in build_parser()._subparsers._group_actions[0].choices["compress"]
                   ._actions if a.dest == "partition").choices
    assert tuple(choices) == tuple(PARTITIONS)  # the command line's list is the coder's


@pytest.mark.slow
def test_the_deblocking_filter_from_the_command_line(tmp_path, png, capsys):
    import subprocess
    import sys

    from ifslib.compression import read

    packed = tmp_path / "off.ifsc"
    assert main(["compress", str(png), "-o", str(packed), "--bpp", "1.0", "--deblock", "0", "--quiet"]) == 0
    assert read(packed).options.deblock == 0 and packed.read_bytes()[4] == 2
    assert "deblocking 0;" in capsys.readouterr().out
    packed = tmp_path / "on.ifsc"
    run = subprocess.run([sys.executable, "-m", "ifslib", "compress", str(png), "-o", str(packed), "--bpp", "1.0",
                          "--deblock", "0.2", "--quiet"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert read(packed).options.deblock in (0, 0.2) and f"deblocking {read(packed).options.deblock:g};" in run.stdout
    for bad in ("0.6", "-0.1", "0.123", "x"):
        run = subprocess.run([sys.executable, "-m", "ifslib", "compress", str(png), "-o", str(tmp_path / "b.ifsc"),
                              "--bpp", "1.0", "--deblock", bad], capture_output=True, text=True)
        assert run.returncode == 2 and "--deblock" in run.stderr and not (tmp_path / "b.ifsc").exists()


@pytest.mark.parametrize("mode, top", [("L", 255), ("RGB", 255), ("I;16", 65535)])
def test_an_image_file_is_read_as_gray_levels_in_0_1_unclipped(tmp_path, mode, top):
    gray = photo(40).numpy().astype(float)
    levels = (gray * top).round()
    path = tmp_path / f"photo-{mode.replace(';', '')}.png"
    if mode == "I;16":
        Image.fromarray(levels.astype(np.uint16)).save(path)  # a 16-bit gray PNG
    else:
        Image.fromarray(levels.astype(np.uint8)).convert(mode).save(path)
    assert Image.open(path).mode == mode
    read = read_gray(str(path))
    assert read.shape == (40, 40) and read.dtype == np.float32
    # Pillow's luma of an RGB gray is the gray itself; a 16-bit file keeps its 65536 levels (not clipped at 255)
    assert np.abs(read - levels / top).max() < 1e-6
    assert (read == 1).mean() == (levels == top).mean()


def test_a_16_bit_png_compresses_as_its_photograph(tmp_path, capsys):
    path, packed, out = tmp_path / "photo16.png", tmp_path / "photo16.ifsc", tmp_path / "out.png"
    gray = photo(48).numpy().astype(float)
    Image.fromarray((gray * 65535).round().astype(np.uint16)).save(path)
    assert main(["compress", str(path), "-o", str(packed), "--bpp", "1.0", "--method", "collage", "--quiet"]) == 0
    assert main(["decompress", str(packed), "-o", str(out)]) == 0
    decoded = np.asarray(Image.open(out), dtype=float) / 255
    assert np.abs(decoded - gray).mean() < 0.08  # read as white, the decoding would be ~0.5 away


def test_float_levels_outside_0_1_are_refused(tmp_path):
    path = tmp_path / "wide.tif"
    Image.fromarray(photo(16).numpy() * 300, mode="F").save(path)
    with pytest.raises(ValueError, match="save it with 8 or 16 bits"):
        read_gray(str(path))


@pytest.mark.parametrize("name, ok", [("out.tif", True), ("out.pgm", True), ("out.jpg", False), ("out", False)])
def test_decompress_writes_a_lossless_format_named_by_the_extension(tmp_path, png, capsys, name, ok):
    packed = tmp_path / "photo.ifsc"
    assert main(["compress", str(png), "-o", str(packed), "--bpp", "1.0", "--method", "collage", "--quiet"]) == 0
    capsys.readouterr()
    assert main(["decompress", str(packed), "-o", str(tmp_path / name)]) == (0 if ok else 2)
    if ok:
        assert Image.open(tmp_path / name).size == (48, 48)
    else:
        err = capsys.readouterr().err
        assert "must end in one of .png" in err and not (tmp_path / name).exists()


def test_quality_instead_of_a_rate(tmp_path, png):
    assert main(["compress", str(png), "-o", str(tmp_path / "q.ifsc"), "--quality", "28", "--method", "collage"]) == 0


@pytest.mark.parametrize("argv, words", [
    (["compress", "MISSING.png", "-o", "x.ifsc", "--bpp", "1"], "no image file"),
    (["decompress", "PNG", "-o", "x.png"], "IFSC"),
    (["decompress", "MISSING.ifsc", "-o", "x.png"], "no compressed file"),
    (["compress", "PNG", "-o", "x.ifsc", "--bpp", "0.001"], "too few"),
    (["compress", "PNG", "-o", "x.ifsc", "--quality", "28", "--partition", "hv"], "give --bpp"),
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
    said = capsys.readouterr().out
    assert "--method {collage,attractor}" in said and "--deblock W" in said
    with pytest.raises(SystemExit):
        main(["decompress", "--help"])
    said = " ".join(capsys.readouterr().out.split())
    assert "0.5 for the default 4 px blocks" in said and "picked by the extension" in said
