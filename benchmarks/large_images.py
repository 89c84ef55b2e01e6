"""Memory and time of `ifslib.load_target` on very large image files (8000² by default).

Writes one figure (a dark triangle on white) as a gray PNG, an RGB JPEG (quality 75), a
black-on-transparent RGBA PNG and a 16-bit PNG into a temporary folder, then loads each at 256² in a
fresh process and prints its peak resident memory (``VmHWM``), over what ``import ifslib``
alone holds, the seconds it took and the polarity it found. A large image is reduced while it is
read (`ifslib.core.targets.image.READ_SIDE`), so the peak follows the decoded file, not float copies of it.

    python benchmarks/large_images.py [--side 8000] [--size 256]
"""
from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

from PIL import Image, ImageDraw

PROBE = """
import resource, sys, time
import ifslib

def peak_mib():
    # the high-water mark of this process's own memory: ru_maxrss would keep the parent's across exec
    try:
        with open("/proc/self/status") as status:
            return next(int(line.split()[1]) for line in status if line.startswith("VmHWM:")) / 1024
    except OSError:
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024

before = peak_mib()
t0 = time.perf_counter()
target = ifslib.load_target(sys.argv[1], int(sys.argv[2]))
seconds = time.perf_counter() - t0
peak = peak_mib()
print(f"{peak - before:.0f}|{peak:.0f}|{seconds:.2f}|{target.mask.mean():.3f}|{target.polarity}")
"""


def write_images(folder: Path, side: int) -> dict[str, Path]:
    triangle = [(side * 0.1, side * 0.9), (side * 0.9, side * 0.9), (side * 0.5, side * 0.1)]
    gray = Image.new("L", (side, side), 255)
    ImageDraw.Draw(gray).polygon(triangle, fill=0)
    rgba = Image.new("RGBA", (side, side), (0, 0, 0, 0))
    ImageDraw.Draw(rgba).polygon(triangle, fill=(0, 0, 0, 255))
    files = {"gray PNG": folder / "gray.png", "RGB JPEG q75": folder / "rgb.jpg",
             "RGBA PNG, black on transparent": folder / "rgba.png", "16-bit PNG": folder / "gray16.png"}
    gray.save(files["gray PNG"])
    gray.convert("RGB").save(files["RGB JPEG q75"], quality=75)
    rgba.save(files["RGBA PNG, black on transparent"])
    gray.convert("I").point(lambda v: v * 257).convert("I;16").save(files["16-bit PNG"])
    return files


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--side", type=int, default=8000, help="pixels a side of the images (default 8000)")
    parser.add_argument("--size", type=int, default=256, help="target size (default 256)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        files = write_images(Path(tmp), args.side)
        print(f"`load_target(file, {args.size})` of {args.side}x{args.side} images, one fresh process each")
        print("| image | peak MiB over `import ifslib` | peak MiB | s | figure share | polarity |")
        print("|---|---|---|---|---|---|")
        for name, path in files.items():
            out = subprocess.run([sys.executable, "-c", PROBE, str(path), str(args.size)], capture_output=True,
                                 text=True, check=True).stdout.strip().split("|")
            print(f"| {name} | {' | '.join(out)} |")


if __name__ == "__main__":
    main()
