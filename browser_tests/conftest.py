"""Fixtures for the browser tests: a headless JupyterLab on a copy of the notebooks, and Chromium.

The tests drive Debian's Chromium (``/usr/bin/chromium``, or ``$IFSLIB_CHROMIUM``) through Playwright's
sync API; nothing here downloads a browser. Without Chromium or the ``playwright`` package every test
fails at setup (pytest reports an ERROR, never a skip) with the way to install them:
``sh browser_tests/setup.sh``.

JupyterLab serves a temporary folder holding copies of the notebooks (outputs cleared), never
``notebooks/`` itself, with every JupyterLab configuration, settings, workspace and runtime folder
also temporary, autosave off, and news, update checks and the PyPI extension manager turned off:
a run neither changes the repository nor opens a network connection.

Screenshots go to ``build/browser/`` (created on demand).
"""
from __future__ import annotations

import json
import os
import secrets
import shutil
import signal
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
from pathlib import Path
from urllib.parse import urlsplit

import pytest

ROOT = Path(__file__).resolve().parent.parent
SHOTS = ROOT / "build" / "browser"
CHROMIUM = os.environ.get("IFSLIB_CHROMIUM", "/usr/bin/chromium")
CHROMIUM_ARGS = ["--headless=new", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync"]
INSTALL_HINT = ("install them with `sh browser_tests/setup.sh` (as root: `apt-get update && apt-get install -y "
                "chromium`, then `.venv/bin/python -m pip install playwright`; never `playwright install`: "
                "the tests drive the system Chromium)")
SERVER_START_TIMEOUT = 90     # seconds for JupyterLab to answer /api/status
NOTEBOOKS = ("00_explore.ipynb", "00_tutorial.ipynb")

# Settings a fresh JupyterLab reads from its (temporary) user-settings folder.
LAB_SETTINGS = {
    "@jupyterlab/docmanager-extension/plugin": {"autosave": False},
    "@jupyterlab/apputils-extension/notification": {"fetchNews": "false", "checkForUpdates": False},
    # every cell in the DOM (the default virtualises offscreen cells, which hides them from the test)
    "@jupyterlab/notebook-extension/tracker": {"windowingMode": "none"},
}
PAGE_CONFIG = {"disabledExtensions": {"@jupyterlab/apputils-extension:announcements": True}}


def _require(condition: bool, what: str) -> None:
    if not condition:
        pytest.fail(f"the browser tests need {what}: {INSTALL_HINT}", pytrace=False)


@pytest.fixture(scope="session")
def sync_api():
    """Playwright's sync API module (fails, with the install command, when it is missing)."""
    try:
        from playwright import sync_api
    except ImportError:
        _require(False, f"the `playwright` Python package in {sys.executable}")
    return sync_api


@pytest.fixture(scope="session")
def browser(sync_api):
    """One headless Chromium for the session."""
    _require(Path(CHROMIUM).is_file() and os.access(CHROMIUM, os.X_OK), f"Chromium at {CHROMIUM}")
    with sync_api.sync_playwright() as p:
        chromium = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, timeout=60_000)
        yield chromium
        chromium.close()


@pytest.fixture
def page(browser):
    """A fresh page (own context: no shared storage) at a size that fits the explorer.

    Records the browser console's errors (``page.console_errors``) and every request to a host other
    than this machine (``page.external_requests``).
    """
    context = browser.new_context(viewport={"width": 1400, "height": 1000}, device_scale_factor=1)
    context.set_default_timeout(30_000)
    page = context.new_page()
    page.console_errors, page.external_requests = [], []
    page.on("console", lambda msg: msg.type == "error" and page.console_errors.append(msg.text))
    page.on("pageerror", lambda exc: page.console_errors.append(f"pageerror: {exc}"))
    page.on("request", lambda req: _is_external(req.url) and page.external_requests.append(req.url))
    yield page
    context.close()


@pytest.fixture(scope="session")
def shots() -> Path:
    SHOTS.mkdir(parents=True, exist_ok=True)
    return SHOTS


def _is_external(url: str) -> bool:
    parts = urlsplit(url)
    return parts.scheme in ("http", "https", "ws", "wss") and parts.hostname not in ("127.0.0.1", "localhost")


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _fresh_copy(src: Path, dst: Path) -> None:
    """``src`` with outputs, execution counts and saved widget state removed (what a newcomer opens)."""
    nb = json.loads(src.read_text(encoding="utf-8"))
    for cell in nb["cells"]:
        if cell["cell_type"] == "code":
            cell["outputs"], cell["execution_count"] = [], None
    nb.get("metadata", {}).pop("widgets", None)
    dst.write_text(json.dumps(nb, indent=1, ensure_ascii=False) + "\n", encoding="utf-8")


class Lab:
    """A running JupyterLab: ``url(path)`` is a page's address with the token."""

    def __init__(self, proc: subprocess.Popen, port: int, token: str, root: Path, log: Path):
        self.proc, self.port, self.token, self.root, self.log = proc, port, token, root, log
        self.base = f"http://127.0.0.1:{port}"

    def url(self, path: str) -> str:
        return f"{self.base}/{path.lstrip('/')}?token={self.token}"

    def cells(self, name: str) -> list[dict]:
        """The cells of the served copy of notebook ``name``."""
        return json.loads((self.root / name).read_text(encoding="utf-8"))["cells"]

    def log_tail(self, chars: int = 4000) -> str:
        return self.log.read_text(errors="replace")[-chars:] if self.log.exists() else ""

    def _request(self, path: str, method: str = "GET", timeout: float = 5):
        req = urllib.request.Request(self.base + path, method=method,
                                     headers={"Authorization": f"token {self.token}"})
        with urllib.request.urlopen(req, timeout=timeout) as resp:
            return resp.status, resp.read()

    def shutdown_kernels(self) -> None:
        """Stop every kernel (a test's notebook kernel would otherwise keep its memory till the end)."""
        try:
            kernels = json.loads(self._request("/api/kernels")[1])
            for kernel in kernels:
                self._request(f"/api/kernels/{kernel['id']}", method="DELETE", timeout=15)
        except (urllib.error.URLError, ConnectionError, TimeoutError, OSError):
            pass

    def wait_until_up(self, timeout: float = SERVER_START_TIMEOUT) -> None:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if self.proc.poll() is not None:
                pytest.fail(f"JupyterLab exited with {self.proc.returncode}:\n{self.log_tail()}", pytrace=False)
            try:
                if self._request("/api/status", timeout=2)[0] == 200:
                    return
            except (urllib.error.URLError, ConnectionError, TimeoutError, OSError):
                pass
            time.sleep(0.25)
        pytest.fail(f"JupyterLab did not answer within {timeout} s:\n{self.log_tail()}", pytrace=False)

    def stop(self) -> None:
        """Ask the server to shut down (it stops its kernels), then end its process group."""
        if self.proc.poll() is None:
            try:
                self._request("/api/shutdown", method="POST")
            except (urllib.error.URLError, ConnectionError, TimeoutError, OSError):
                pass
            try:
                self.proc.wait(timeout=15)
            except subprocess.TimeoutExpired:
                pass
        for sig in (signal.SIGTERM, signal.SIGKILL):   # kernels left behind share the group
            try:
                os.killpg(self.proc.pid, sig)
            except ProcessLookupError:
                break
            try:
                self.proc.wait(timeout=5)
            except subprocess.TimeoutExpired:
                continue
            if sig is signal.SIGTERM:
                time.sleep(0.2)


@pytest.fixture(scope="session")
def lab(tmp_path_factory) -> Lab:
    """JupyterLab on 127.0.0.1 (free port, random token) serving fresh copies of the notebooks."""
    base = tmp_path_factory.mktemp("jupyterlab")
    root = base / "root"
    root.mkdir()
    for name in NOTEBOOKS:
        _fresh_copy(ROOT / "notebooks" / name, root / name)
    config, settings = base / "config", base / "settings"
    (config / "labconfig").mkdir(parents=True)
    (config / "labconfig" / "page_config.json").write_text(json.dumps(PAGE_CONFIG))
    for plugin, values in LAB_SETTINGS.items():
        path = settings / f"{plugin}.jupyterlab-settings"
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(values))

    env = dict(os.environ)
    env.pop("MPLBACKEND", None)      # the kernel's own default: inline figures, as a user sees them
    if not env.get("IFSLIB_DATA") and (ROOT.parent / "shared" / "data" / "koch.png").is_file():
        env["IFSLIB_DATA"] = str(ROOT.parent / "shared" / "data")   # as the Makefile does
    env.update(JUPYTER_CONFIG_DIR=str(config), JUPYTER_DATA_DIR=str(base / "data"),
               JUPYTER_RUNTIME_DIR=str(base / "runtime"), JUPYTERLAB_SETTINGS_DIR=str(settings),
               JUPYTERLAB_WORKSPACES_DIR=str(base / "workspaces"), IPYTHONDIR=str(base / "ipython"),
               JUPYTER_PLATFORM_DIRS="1", PYTHONUNBUFFERED="1")
    port, token = _free_port(), secrets.token_hex(24)
    jupyter = Path(sys.executable).parent / "jupyter"
    _require(jupyter.exists(), f"JupyterLab ({jupyter}; `make setup` installs it)")
    cmd = [str(jupyter), "lab",
           "--no-browser", "--ServerApp.ip=127.0.0.1", f"--ServerApp.port={port}",
           "--ServerApp.port_retries=0", f"--IdentityProvider.token={token}", f"--ServerApp.root_dir={root}",
           "--ServerApp.terminals_enabled=False", "--LabApp.news_url=None",
           "--LabApp.check_for_updates_class=jupyterlab.handlers.announcements.NeverCheckForUpdate",
           "--LabApp.extension_manager=readonly", "--LabApp.workspaces_dir=" + str(base / "workspaces")]
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        cmd.append("--allow-root")      # CI containers run as root
    log = base / "jupyterlab.log"
    with open(log, "wb") as out:
        proc = subprocess.Popen(cmd, cwd=root, env=env, stdout=out, stderr=subprocess.STDOUT,
                                stdin=subprocess.DEVNULL, start_new_session=True)
    server = Lab(proc, port, token, root, log)
    try:
        server.wait_until_up()
        yield server
    finally:
        server.stop()
        shutil.copy(log, SHOTS / "jupyterlab.log") if SHOTS.is_dir() else None
