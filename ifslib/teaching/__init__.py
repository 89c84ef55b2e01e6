"""Teaching: what the notebooks show and ask. Figures, the explorer widget, animations, exercises
with their checks, and loss landscapes. Imports from everything below it."""
