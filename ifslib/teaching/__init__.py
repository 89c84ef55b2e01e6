"""Teaching: what the notebooks show and ask (figures, the explorer, animations, the exercises, landscapes)."""
# No import here: each module that computes imports ifslib.threads before torch itself, so that the grader's
# scan of a submission (exercises.integrity) loads without torch.
