# nbgrader's configuration for a course made of this project's notebooks (course/grading.py lays the
# course folder out and copies this file into it; an instructor's own course folder can start from it).
c = get_config()  # noqa: F821  (nbgrader provides get_config)

c.CourseDirectory.course_id = "ifslib"
# the lessons with exercises form one assignment per lecture (lecture1 ... lecture7): course/grading.py
# copies them into source/<lecture>/

# A solution region becomes one statement, so that a function body stays valid Python and running the
# student's cell raises nothing: the locked test cell below it says what is missing (nbgrader's default
# stub raises NotImplementedError in the answer cell itself).
c.ClearSolutions.code_stub = {"python": "...  # YOUR CODE HERE"}
c.ClearSolutions.text_stub = "YOUR ANSWER HERE"

# Autograding runs each notebook top to bottom: at the teaching sizes the longest lessons (02, 04, 06)
# take minutes on one CPU thread, each cell well under this limit.
c.ExecutePreprocessor.timeout = 600
# The kernel is killed once its notebook has run rather than asked to shut down and waited for: the
# grades are already read, and the wait (torch's exit) cost about a second a notebook, 11 of the course's
# ~100 s a submission.
c.Execute.shutdown_kernel = "immediate"

# Tests that do not trust the student's kernel (nbgrader_checks.py, copied beside this file): the
# student's cells are read before the notebook runs, and the tests their tricks could fool get 0;
# feedback leaves out the hidden tests and the tracebacks that would quote them.
import os  # noqa: E402
import sys  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from nbconvert.preprocessors import ClearMetadataPreprocessor, CSSHTMLHeaderPreprocessor  # noqa: E402
from nbgrader.preprocessors import (AssignLatePenalties, CheckCellMetadata, ClearOutput,  # noqa: E402
                                    DeduplicateIds, Execute, GetGrades, IgnorePattern, LimitOutput,
                                    OverwriteKernelspec, SaveAutoGrades)
from nbgrader_checks import FailFooled, HideTests, OverwriteCells, ScanCells  # noqa: E402

c.Autograde.sanitize_preprocessors = [ClearOutput, DeduplicateIds, OverwriteKernelspec, OverwriteCells,
                                      CheckCellMetadata]

c.Autograde.autograde_preprocessors = [ScanCells, Execute, FailFooled, IgnorePattern, ClearMetadataPreprocessor,
                                       LimitOutput, SaveAutoGrades, AssignLatePenalties, CheckCellMetadata]
c.GenerateFeedback.preprocessors = [GetGrades, HideTests, CSSHTMLHeaderPreprocessor]
