"""``ifslib fit IMAGE --strategy splat`` in a subprocess, at a tiny size: it fits, saves and scores the attractor."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest
import torch
from PIL import Image

import ifslib
from ifslib.core.geometry import patterns

THREE = torch.tensor([[[0.5, 0.0, -0.2], [0.0, 0.5, -0.2], [0, 0, 1]],
                      [[0.5, 0.0, 0.2], [0.0, 0.5, -0.2], [0, 0, 1]],
                      [[0.5, 0.0, 0.0], [0.0, 0.5, 0.2], [0, 0, 1]]], dtype=torch.float64)


@pytest.mark.slow
def test_the_command_line_fits_with_the_splat_strategy(tmp_path):
    picture = ifslib.render(patterns.affine(THREE, depth=4, dtype=torch.float64), 32).detach().numpy()
    image = tmp_path / "three.png"
    Image.fromarray(((picture >= 0.5) * 255).astype(np.uint8)).save(image)
    moved = THREE.clone()
    moved[:, :2, 2] += 0.03
    start = tmp_path / "start.json"
    ifslib.save_ifs(patterns.affine(moved, depth=3, dtype=torch.float64), start)
    out = tmp_path / "fit.json"
    env = dict(os.environ, IFSLIB_THREADS="1")
    done = subprocess.run([sys.executable, "-m", "ifslib", "fit", str(image), "--pattern", str(start), "--size", "32",
                           "--steps", "40", "--strategy", "splat", "--jitter", "0", "--quiet", "-o", str(out)],
                          capture_output=True, text=True, env=env, timeout=300)
    assert done.returncode == 0, done.stderr
    assert "40 steps spent (splat)" in done.stdout and "attractor: IoU" in done.stdout
    saved = json.loads(out.read_text())
    assert saved["meta"]["history"]["strategy"] == "splat" and len(saved["rules"]) == 3
    assert 0 < saved["meta"]["scores"]["attractor"]["iou"] <= 1
    assert abs(sum(saved["probabilities"]) - 1) < 1e-6
