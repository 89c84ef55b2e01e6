"""Driving JupyterLab 4 from Playwright: open a notebook, run it, edit and run one cell, find errors.

Everything waits on a condition (the kernel's status, the cells' prompts), with a bounded timeout;
nothing sleeps a fixed time. Selectors are JupyterLab 4's (``.jp-NotebookPanel``, ``.jp-CodeCell``,
``.jp-InputArea-prompt``, ``.cm-content``) and ipywidgets 8's (``.widget-hslider``, ``.noUi-handle``).
"""
from __future__ import annotations

import io
import re
import time

import numpy as np
import pytest
from PIL import Image

PANEL = ".jp-NotebookPanel:not(.lm-mod-hidden)"
STDERR = '.jp-OutputArea-output[data-mime-type="application/vnd.jupyter.stderr"]'
ERROR_WORDS = re.compile(r"Traceback|Error|Exception")
WIDGET_ERRORS = ("Error displaying widget", "Failed to load model", "Could not create a view",
                 "Could not create a model", "Failed to create view", "Model not found")

# The kernel's state as the status bar shows it ("Python 3 (ipykernel) | Idle").
_KERNEL_STATUS = """() => {
  const bar = document.querySelector('#jp-main-statusbar');
  if (!bar) return '';
  const item = [...bar.querySelectorAll('*')].find(e => e.children.length === 0 && / \\| \\S+/.test(e.textContent));
  return item ? item.textContent.trim() : '';
}"""

# Null while the notebook is still running; then 'done', 'error: <text>' or 'kernel: <status>'.
_RUN_STATE = """(stderrSelector) => {
  const panel = document.querySelector('%s');
  if (!panel) return null;
  const status = (%s)();
  if (/\\| (Dead|Unknown|Restarting)/.test(status)) return 'kernel: ' + status;
  const prompts = [...panel.querySelectorAll('.jp-CodeCell .jp-InputArea-prompt')].map(p => p.textContent.trim());
  const running = prompts.some(p => p.includes('*'));
  if (running) return null;
  const errors = [...panel.querySelectorAll(stderrSelector)].map(e => e.innerText)
                                                             .filter(t => /Traceback|Error/.test(t));
  if (errors.length) return 'error: ' + errors[0];
  const done = prompts.length > 0 && prompts.every(p => /^\\[\\d+\\]:$/.test(p));
  return done && / \\| Idle$/.test(status) ? 'done' : null;
}""" % (PANEL, _KERNEL_STATUS)


# True once the notebook shows all its cells and its kernel is idle.
_OPENED = """(n) => {
  const cells = document.querySelectorAll('%s .jp-Notebook .jp-Cell');
  return cells.length >= n && / \\| Idle$/.test((%s)());
}""" % (PANEL, _KERNEL_STATUS)


def kernel_status(page) -> str:
    return page.evaluate(_KERNEL_STATUS)


def open_notebook(page, lab, name: str, timeout_s: float = 90) -> None:
    """Open ``name`` (a path under the server's root) and wait for its cells and an idle kernel."""
    # a workspace of its own: JupyterLab would otherwise reopen the notebooks an earlier test opened
    page.goto(lab.url(f"lab/workspaces/{name.replace('.', '-')}/tree/{name}"))
    n_cells = len(lab.cells(name))
    try:
        page.wait_for_function(_OPENED, arg=n_cells, timeout=timeout_s * 1000, polling=250)
    except Exception as exc:
        pytest.fail(f"{name} did not open with an idle kernel within {timeout_s} s "
                    f"(status bar: {kernel_status(page)!r}): {exc}\n--- JupyterLab log:\n{lab.log_tail()}",
                    pytrace=False)


def run_all(page, name: str, timeout_s: float) -> float:
    """Run > Run All Cells through the menu bar; wait until every code cell has run. Returns seconds."""
    page.get_by_role("menuitem", name="Run", exact=True).click()
    page.locator(".lm-Menu .lm-Menu-item", has=page.get_by_text("Run All Cells", exact=True)).click()
    started = time.monotonic()
    try:
        handle = page.wait_for_function(_RUN_STATE, arg=STDERR, timeout=timeout_s * 1000, polling=250)
    except Exception:
        prompts = page.locator(f"{PANEL} .jp-CodeCell .jp-InputArea-prompt").all_inner_texts()
        pytest.fail(f"{name}: Run All Cells did not finish within {timeout_s} s; prompts {prompts}, "
                    f"kernel {kernel_status(page)!r}", pytrace=False)
    state = handle.json_value()
    assert state == "done", f"{name}: Run All Cells ended with {state}"
    return time.monotonic() - started


def code_cell(page, contains: str):
    """The code cell whose source contains ``contains`` (a locator that stays valid when it is edited)."""
    cells = page.locator(f"{PANEL} .jp-CodeCell")
    for i in range(cells.count()):
        if contains in cells.nth(i).locator(".cm-content").inner_text():
            return cells.nth(i)
    raise AssertionError(f"no code cell contains {contains!r}")


def replace_and_run(page, cell, source: str, timeout_s: float = 60) -> None:
    """Type ``source`` over the cell's text (as a user would), Shift+Enter, wait for its new prompt."""
    cell.locator(".cm-content").click()
    page.keyboard.press("ControlOrMeta+a")
    page.keyboard.insert_text(source)     # as pasted text: no auto-closed brackets, no completer
    assert cell.locator(".cm-content").inner_text().strip() == source.strip(), "the editor did not take the text"
    run_cell(page, cell, timeout_s)


def run_cell(page, cell, timeout_s: float = 60) -> None:
    """Run the cell as it stands (click into it, Shift+Enter) and wait for its new prompt.

    A long cell is not retyped: CodeMirror draws only the lines in view, so its text as read from the
    page is not the whole source.
    """
    prompt = cell.locator(".jp-InputArea-prompt")
    before = prompt.inner_text().strip()
    cell.locator(".cm-content").click()
    page.keyboard.press("Shift+Enter")
    page.wait_for_function(
        """([el, before]) => { const p = el.textContent.trim(); return /^\\[\\d+\\]:$/.test(p) && p !== before; }""",
        arg=[prompt.element_handle(), before], timeout=timeout_s * 1000, polling=100)


def outputs_text(locator) -> str:
    return "\n".join(locator.locator(".jp-OutputArea-output").all_inner_texts())


def problems(page, scope=None) -> list[str]:
    """Error outputs, stderr that reads like an error, widgets that failed to display, widget console errors."""
    root = scope if scope is not None else page.locator(PANEL)
    found = [f"stderr output: {t[:600]}" for t in root.locator(STDERR).all_inner_texts() if ERROR_WORDS.search(t)]
    text = root.first.inner_text()
    found += [f"page shows {w!r}" for w in WIDGET_ERRORS if w in text]
    found += [f"browser console: {m[:300]}" for m in getattr(page, "console_errors", [])
              if re.search(r"widget|ipywidgets|jupyter-widgets|\bcomm\b", m, re.I)]
    return found


def png(data: bytes) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(data)).convert("RGB"))
