"""The names a user gives the library, with their defaults, in a module that imports nothing: the command line
refuses a misspelt name before torch is loaded."""

#: A fit's step budget and learning rate when none is given: the paper's run (1500 Adam steps at 0.003),
#: for the library, the command line and the sweep alike.
DEFAULT_STEPS = 1500
DEFAULT_LR = 0.003

#: The losses `ifslib.core.scoring.losses.loss` computes, by name.
LOSSES = ("pixel", "multiscale_pixel", "distance", "multiscale_distance")

#: The loss of a fit when none is named: the distance loss pulls a copy towards the figure from anywhere in
#: the frame (a pixel loss is flat away from the strokes); the multiscale sum is the paper's.
DEFAULT_LOSS = "multiscale_distance"

#: The strategies `ifslib.fit` runs, by name.
STRATEGIES = ("pyramid", "auto", "plain", "coarse_to_fine", "multistart", "restart", "anneal", "uncross", "splat")

#: What `ifslib.fit` does when given no strategy.
DEFAULT_STRATEGY = "pyramid"

#: The coders `ifslib.compression.compress` runs: the classic collage coder, and the same bits refined
#: through the decoder (attractor coding).
COMPRESSION_METHODS = ("collage", "attractor")

#: The partitions of a compressed photograph (`ifslib.compression.partitions`), in the order a file's header
#: numbers them (the first the default), each with the command line's phrase for it.
PARTITIONS = {"quadtree": "squares split in four", "hv": "rectangles cut at their strongest edge; with --bpp"}
