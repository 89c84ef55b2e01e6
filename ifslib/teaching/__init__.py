"""Teaching: what the notebooks show and ask. Figures, the explorer widget, animations, the
exercises' harness and targets (no answer key: those live in the instructor's notebooks), and loss
landscapes. Imports from everything below it."""
# No import here: each module that computes imports ifslib.threads before torch itself, so that the grader's
# scan of a submission (exercises.integrity) loads without torch.
