# nbgrader's configuration for a course made of this project's notebooks (course/grading.py lays the
# course folder out and copies this file into it; an instructor's own course folder can start from it).
c = get_config()  # noqa: F821  (nbgrader provides get_config)

c.CourseDirectory.course_id = "ifslib"
# the lessons with exercises form one assignment, "ifs": course/grading.py copies them into source/ifs/

# A solution region becomes one statement, so that a function body stays valid Python and running the
# student's cell raises nothing: the locked test cell below it says what is missing (nbgrader's default
# stub raises NotImplementedError in the answer cell itself).
c.ClearSolutions.code_stub = {"python": "...  # YOUR CODE HERE"}
c.ClearSolutions.text_stub = "YOUR ANSWER HERE"

# Autograding runs each notebook top to bottom: at the teaching sizes the longest lessons (02, 04, 06)
# take minutes on one CPU thread, each cell well under this limit.
c.ExecutePreprocessor.timeout = 600
