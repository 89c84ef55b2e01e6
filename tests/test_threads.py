"""The thread count: fixed by IFSLIB_THREADS or a call, or picked from the cores other processes leave free."""
import subprocess
import sys
import time

import pytest
import torch

import ifslib
from ifslib import threads
from ifslib.errors import IFSError


def is_auto() -> bool:
    """Whether the thread count follows the free cores (``IFSLIB_THREADS`` unset or ``auto``)."""
    return threads._state["auto"]


@pytest.fixture(autouse=True)
def restore_threads():
    saved = (is_auto(), torch.get_num_threads())
    yield
    threads._state["auto"] = saved[0]
    torch.set_num_threads(saved[1])


@pytest.fixture
def spinner():
    """Another process keeping one core busy."""
    proc = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    time.sleep(0.5)
    yield proc
    proc.kill()
    proc.wait()


def test_a_number_fixes_the_count_and_auto_follows_the_free_cores(monkeypatch):
    assert ifslib.configure_threads(1) == 1 and not is_auto()
    assert threads.refresh() == 1  # fixed: refresh keeps it
    n = ifslib.configure_threads("auto")
    assert is_auto() and 1 <= n <= threads.cores()
    monkeypatch.setenv("IFSLIB_THREADS", "1")
    assert ifslib.configure_threads() == 1 and not is_auto()
    for unset in ("", " auto ", "AUTO"):
        monkeypatch.setenv("IFSLIB_THREADS", unset)
        ifslib.configure_threads()
        assert is_auto()


@pytest.mark.parametrize("bad", ["x", "0", "-2", "1.5", 0, -1, True, 1.5])
def test_bad_thread_counts_are_clear_errors(bad, monkeypatch):
    with pytest.raises(IFSError, match="'auto' or a positive integer"):
        ifslib.configure_threads(bad)
    monkeypatch.setenv("IFSLIB_THREADS", str(bad))
    with pytest.raises(IFSError, match="IFSLIB_THREADS"):
        ifslib.configure_threads()


def test_fixed_threads_restores_the_setting():
    ifslib.configure_threads("auto")
    with threads.fixed_threads(1) as n:
        assert n == 1 and not is_auto()
        assert threads.refresh() == 1
    assert is_auto()


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="busy cores are read from /proc")
def test_a_busy_core_is_seen_and_left_alone(spinner):
    busy = threads.busy_cores(0.5)
    assert 0.6 <= busy <= threads.cores() + 0.5
    assert threads.free_threads() <= max(1, threads.cores() - 1)
    ifslib.configure_threads("auto")
    assert torch.get_num_threads() <= max(1, threads.cores() - 1)


def test_refresh_looks_again_only_after_a_while(monkeypatch):
    ifslib.configure_threads("auto")
    looked = []
    monkeypatch.setattr(threads, "busy_cores", lambda: looked.append(1) or 0.0)
    threads.refresh()
    assert looked == []  # configure_threads has just looked
    monkeypatch.setitem(threads._state, "sampled", time.monotonic() - threads.REFRESH_SECONDS)
    assert threads.refresh() == threads.cores()  # nothing else busy (as the stub says): every core
    assert looked == [1]


def _top_imports(path):
    """The module names a file's top-level statements import, in order (``threads`` for a relative import of it)."""
    import ast

    names = []
    for node in ast.parse(path.read_text()).body:
        if isinstance(node, ast.Import):
            names += [a.name.split(".")[0] for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            module = node.module or ""
            names += ["threads"] if module.endswith("threads") or any(a.name == "threads" for a in node.names) \
                else [module.split(".")[0] if not node.level else module]
    return names


def test_every_module_loads_torch_after_the_thread_settings():
    """``OMP_WAIT_POLICY`` counts only when set before torch loads: each module that imports torch at its top
    imports ``ifslib.threads`` first, or a folder above it does (its ``__init__.py``, before any torch)."""
    from pathlib import Path

    package = Path(ifslib.__file__).parent
    early = []
    for path in sorted(package.rglob("*.py")):
        names = _top_imports(path)
        if "torch" not in names or path.name == "threads.py":
            continue
        if "threads" in names[: names.index("torch")]:
            continue
        folders = [path.parent] + [p for p in path.parent.parents if package in (p, *p.parents)]
        inits = [f / "__init__.py" for f in folders if f != package and (f / "__init__.py").exists() and f / "__init__.py" != path]
        if any("threads" in (n := _top_imports(i)) and ("torch" not in n or n.index("threads") < n.index("torch"))
               for i in inits):
            continue
        early.append(str(path.relative_to(package)))
    assert not early, f"these import torch before ifslib.threads: {early}"


def test_importing_ifslib_writes_nothing_to_the_environment():
    import subprocess
    import sys

    code = ("import os; before = dict(os.environ); import ifslib; ifslib.__all__; assert dict(os.environ) == before; "
            "ifslib.load_target; assert os.environ['OMP_WAIT_POLICY'] and os.environ['MKL_CBWR']")
    env = {k: v for k, v in __import__("os").environ.items() if k not in ("OMP_WAIT_POLICY", "MKL_CBWR")}
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert done.returncode == 0, done.stderr[-1500:]
