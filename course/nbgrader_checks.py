"""nbgrader's autograde, made not to trust the student's kernel: read the cells a student wrote before
running them, and give no points to the tests that code could have fooled.

`ScanCells` runs before nbgrader's ``Execute``: it reads the submission's answer cells and the cells the
student added (every lesson cell is locked in the release, so nbgrader restores it) with
`ifslib.teaching.exercises.integrity.scan`, in this process, where nothing the kernel runs can reach.
`FailFooled` runs after ``Execute``: each test the findings touch gets an error output naming the cell
and the construct, so nbgrader scores it 0 and the feedback says why. A finding that rebinds a name
touches every test after its cell; a banned mention touches its own exercise's test.
`OverwriteCells` is nbgrader's, without the tamper alarm it raises on every released test cell (they
lack their hidden tests). `HideTests` is for ``generate_feedback``: the hidden tests' lines out of the test cells and each
error's traceback reduced to its message, so that the feedback holds no line of a hidden test.

``course/nbgrader_config.py`` puts them in nbgrader's pipelines; ``course/grading.py`` copies this file
and ``notebook_scan.py`` beside it.
"""
from __future__ import annotations

import re

from nbformat.v4 import new_output
from nbgrader.api import Gradebook, MissingEntry
from nbgrader.preprocessors import NbGraderPreprocessor
from nbgrader.preprocessors import OverwriteCells as _OverwriteCells

from notebook_scan import BANS, is_students, nbgrader_meta, scan_notebook  # beside this file (course/grading.py)

SOLUTION = re.compile(r"### BEGIN SOLUTION.*?### END SOLUTION", re.S)
HIDDEN = re.compile(r"[ \t]*### BEGIN HIDDEN TESTS.*?### END HIDDEN TESTS[ \t]*\n?", re.S)


class ScanCells(NbGraderPreprocessor):
    """Read the student's cells for what changes the checks (before the notebook runs)."""

    def preprocess(self, nb, resources):
        stubs = self._stubs(resources, [c for c in nb.cells if is_students(c)])
        found = scan_notebook(nb, stubs, BANS)
        resources.setdefault("ifslib_findings", {})[resources["unique_key"]] = found
        for _, finding in found:
            self.log.warning("untrusted: %s: %s", resources["unique_key"], finding)
        return nb, resources

    def _stubs(self, resources, cells) -> dict[str, str]:
        """grade_id -> the answer cell as released (the source's solution cut out): the names it asks for."""
        info = resources.get("nbgrader", {})
        out = {}
        try:
            with Gradebook(info["db_url"]) as book:
                for cell in cells:
                    name = nbgrader_meta(cell).get("grade_id")
                    if name:
                        try:
                            source = book.find_source_cell(name, info["notebook"], info["assignment"]).source
                        except MissingEntry:
                            continue
                        out[name] = SOLUTION.sub("...", source)
        except KeyError:   # run outside nbgrader (a test): each answer's own cell is its stub
            out = {nbgrader_meta(c).get("grade_id"): SOLUTION.sub("...", c.source) for c in cells if nbgrader_meta(c).get("grade_id")}
        return out


class FailFooled(NbGraderPreprocessor):
    """Give an error output, so 0 points, to every test the findings of `ScanCells` touch (after it ran)."""

    def preprocess(self, nb, resources):
        findings = resources.get("ifslib_findings", {}).get(resources["unique_key"], [])
        for index, finding in findings:
            later = [k for k in range(index + 1, len(nb.cells)) if nbgrader_meta(nb.cells[k]).get("grade")
                     and nb.cells[k].cell_type == "code"]
            touched = later[:1] if finding.kind == "uses the library's answer" else later
            for k in touched:
                nb.cells[k].outputs.append(new_output(
                    "error", ename="NotTrusted", evalue=f"{finding}: this test is not trusted and gets no points",
                    traceback=[f"NotTrusted: {finding}"]))
        return nb, resources


class HideTests(NbGraderPreprocessor):
    """Feedback without the hidden tests: their lines cut from the test cells, tracebacks cut to their message."""

    def preprocess(self, nb, resources):
        for cell in nb.cells:
            if cell.cell_type != "code" or not nbgrader_meta(cell).get("grade"):
                continue
            cell.source = HIDDEN.sub("", cell.source)
            for output in cell.get("outputs", []):
                if output.output_type == "error":
                    output.traceback = [f"{output.ename}: {output.evalue}"]
        return nb, resources


class OverwriteCells(_OverwriteCells):
    """nbgrader's ``OverwriteCells``, without its tamper alarm on a test cell handed back as released.

    nbgrader stores a test cell's checksum with its hidden tests and releases the cell without them, so
    every honest submission's test cells read as changed ("Attribute 'checksum' ... has changed"). A
    locked cell whose source is the stored one less its hidden tests is the released cell: it is put
    back whole before nbgrader compares, and only a cell the student did change raises the alarm.
    """

    def preprocess_cell(self, cell, resources, cell_index):
        grade_id = nbgrader_meta(cell).get("grade_id")
        if grade_id and nbgrader_meta(cell).get("locked"):
            try:
                stored = self.gradebook.find_source_cell(grade_id, self.notebook_id, self.assignment_id)
            except MissingEntry:
                stored = None
            if stored is not None and HIDDEN.sub("", stored.source).strip() == cell.source.strip():
                cell.source = stored.source
        return super().preprocess_cell(cell, resources, cell_index)
