"""The splatting renderer's and fit's tuned numbers, one line each on what they trade."""

#: Points a picture splats: 2048 chains (`ifslib.core.raster.chaos.CHAINS`) of 250 points, as Djeacoumar et al.'s
#: 2,000 chains of 250. More, less noise in the gray levels; the step's time grows with them.
POINTS = 2048 * 250

#: Last steps of each chain the gradient runs through: a point's dependence on a map ``j`` steps back shrinks like
#: ``s_max ** j``, so 8 keeps 1 - 0.5 ** 8 of it for maps of scale 0.5; each step holds 48 bytes a point for backward.
GRADIENT_DEPTH = 8

#: Bytes a splat holds per point (its float64 chain point, pick and the read-back's buffers), per point and gradient
#: step (the replayed coordinates and picks kept for backward) and per point and corner (index, weight): 240 bytes a
#: point at depth 8, against a peak of 206 measured (2 million points at 256 px, one thread).
BYTES_PER_POINT = 64
BYTES_PER_POINT_STEP = 16
BYTES_PER_CORNER = 12

#: The largest singular value a fitted map may reach: the parameterization maps onto (0, MAX_SCALE), so every map
#: contracts at every step; nearer 1, larger copies but slower burn-in and a weaker gradient.
MAX_SCALE = 0.95

#: A support target's coverage: a pixel of density ``COVERAGE`` times the target's mean density per figure pixel
#: reads 1 - 1/e. Lower, thin parts count sooner; but a pixel then reads covered on fewer points (noisier).
COVERAGE = 0.1

#: Pooled copies in the multiscale loss: 5 reaches 32-pixel blocks, so a copy far from its place still feels a pull.
LOSS_LEVELS = 5

#: Adam's learning rate for the raw parameters (angles in radians, logits of singular values, translations in plane
#: units) and for the probabilities' logits. 0.03 against 0.01: ten0's attractor IoU 0.736 against 0.638 (600 steps).
MAP_LR = 0.03
PROBABILITY_LR = 0.02

#: Annealing: Gaussian noise added to the raw parameters at each step of the first ``ANNEAL_SHARE`` of the steps, its
#: scale ``ANNEAL_NOISE`` times the learning rate falling linearly to 0 (escape from a local minimum, then settle).
ANNEAL_SHARE = 0.5
ANNEAL_NOISE = 0.25

#: Reselection: every ``RESEED_EVERY`` steps within the first ``RESEED_SHARE`` of the steps, the map that covers least
#: of the figure on its own is placed anew where the figure is least covered; more often, more tries, less settling.
RESEED_EVERY = 60
RESEED_SHARE = 0.6

#: A random start's maps: singular values uniform in this range (a 10-map figure's copies are about a third wide).
START_SCALES = (0.2, 0.45)

#: Coarse-to-fine: the fit runs at the target's size divided by these factors, in order, with these shares of the
#: steps; a level's points are `POINTS_PER_PIXEL` times its pixels (a 64 px level, a sixteenth of 256 px's).
LEVELS = (4, 2, 1)
LEVEL_STEPS = (0.6, 0.25, 0.15)

#: Points a fit's step splats per pixel of the frame (8 at 256 px: Djeacoumar et al.'s 512,000): more, less noise
#: in the loss and its gradient; the step's time grows with them.
POINTS_PER_PIXEL = 8.0

#: Reselection moves a map only while at least this share of the figure is uncovered (a fit that covers it all
#: has nothing to gain from moving a map, and much to lose).
RESEED_UNCOVERED = 0.05

#: The learning rates fall by a cosine to this share of theirs at the last step: lower, finer settling at the end
#: but less movement in the last levels.
FINAL_LR_SHARE = 0.05

#: Random starts screened before a fit from random maps, each for ``SCREEN_STEPS`` steps at a quarter of the size, the
#: best (mean loss of its last ``SCREEN_TAIL`` steps) kept: more starts, fewer fits stuck from the start, each costing
#: about a fifth of a 256 px step per screening step.
STARTS = 6
SCREEN_STEPS = 150
SCREEN_TAIL = 10

#: Reselection's coverage is counted on this many times a step's points: fewer, and a sparse part of a good fit reads
#: uncovered by chance and a good map is moved.
RESEED_POINTS = 4
