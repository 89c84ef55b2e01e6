"""Installing ifslib beside other packages: pyproject.toml declares ranges, constraints.txt pins the tested set.

`pip install ifslib` into an environment that already has torch must keep that torch (an exact pin
would replace it, with a multi-GB download when the index only has CUDA builds); `make setup` and
CI install with ``-c constraints.txt``, so this repository still runs its tests on one known set.
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest

tomllib = pytest.importorskip("tomllib")
from packaging.requirements import Requirement  # noqa: E402
from packaging.version import Version  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]


def _requirements() -> list[Requirement]:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    listed = list(project["dependencies"])
    for extra in project["optional-dependencies"].values():
        listed += extra
    return [Requirement(r) for r in listed]


def _pins() -> dict[str, Version]:
    pins = {}
    for line in (ROOT / "constraints.txt").read_text(encoding="utf-8").splitlines():
        line = line.split("#")[0].strip()
        if line:
            name, version = line.split("==")
            pins[_norm(name)] = Version(version)
    return pins


def _norm(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def test_pyproject_declares_ranges_not_exact_versions():
    exact = [str(r) for r in _requirements() if any(s.operator in ("==", "===") for s in r.specifier)]
    assert not exact, f"pyproject.toml pins exact versions (a pip install would replace what it finds): {exact}"
    torch = next(r for r in _requirements() if r.name == "torch")
    assert torch.specifier.contains("2.13.0+cpu") and torch.specifier.contains("2.5.1"), torch


def test_constraints_pin_every_dependency_inside_its_range():
    pins = _pins()
    for req in _requirements():
        name = _norm(req.name)
        assert name in pins, f"constraints.txt does not pin {req.name} (pyproject.toml asks for {req})"
        assert req.specifier.contains(pins[name], prereleases=True), \
            f"constraints.txt pins {req.name}=={pins[name]}, outside pyproject.toml's {req.specifier}"

