"""Does a fit collapse when the machine is shared? Two default CLI fits started side by side.

For each thread setting (``IFSLIB_THREADS=2``, fixed, and ``auto``, the default: the cores other
processes leave free, picked at every run), the benchmark times one CLI Koch fit alone, then two
fits of two poses started one second apart in two processes, and prints each command's wall time
(whole command, as `cli_poses.py` measures). On a 2-core machine two processes of two threads each
oversubscribe the cores.

    python benchmarks/shared_machine.py [--size 256]
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from cli_poses import fit_command, random_poses, write_pose  # noqa: E402


def side_by_side(commands: list[list[str]], threads: str, delay: float = 1.0) -> list[float]:
    """Start each command ``delay`` seconds after the one before; returns each one's wall time."""
    env = {**os.environ, "IFSLIB_THREADS": threads}
    started, procs = [], []
    for k, command in enumerate(commands):
        if k:
            time.sleep(delay)
        started.append(time.perf_counter())
        procs.append(subprocess.Popen(command, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
    ended = [None] * len(procs)
    while any(e is None for e in ended):
        for k, proc in enumerate(procs):
            if ended[k] is None and proc.poll() is not None:
                if proc.returncode:
                    raise RuntimeError(f"{' '.join(commands[k])} failed ({proc.returncode})")
                ended[k] = time.perf_counter()
        time.sleep(0.05)
    return [e - s for e, s in zip(ended, started)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=256)
    args = parser.parse_args()
    print(f"default CLI Koch fits at {args.size}², {os.cpu_count()} cores; wall time of each command in seconds")
    print("| IFSLIB_THREADS | alone | two side by side |")
    print("|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        pngs = [Path(tmp) / f"pose{k}.png" for k in range(2)]
        for pose, png in zip(random_poses(2), pngs):
            write_pose(pose, args.size, png)
        commands = [fit_command(png, png.with_suffix(".json"), args.size) for png in pngs]
        for threads in ("2", "auto"):
            alone = side_by_side(commands[:1], threads)
            both = side_by_side(commands, threads)
            print(f"| {threads} | {alone[0]:.1f} | {' and '.join(f'{t:.1f}' for t in both)} |", flush=True)


if __name__ == "__main__":
    main()
