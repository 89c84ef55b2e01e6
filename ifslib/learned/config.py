"""The learned guess's tuned numbers, each with what it trades."""

#: Pixels per side of the image the network reads: a target is max-pooled to it. 64 places a map to about
#: 1/64 of the frame, which the refinement then settles; 128 would cost four times the convolutions.
SIZE = 64
#: The slots' grid: a slot a cell of 4 x 4 pixels, whose centre anchors the map whose copy is centred there.
GRID = SIZE // 4
#: The most maps a guess holds: the 10-map set's count.
MAX_MAPS = 10
#: Channels of the encoder's first stage (doubled at each of its four stages).
WIDTH = 16
#: The weight of a linear part's entry against a shift's in the set loss: a map's linear error moves the
#: copy of an attractor of half-width about 0.4 by 0.4 times it, so both terms are in plane units.
LINEAR_WEIGHT = 0.4
#: The weight of the presence score's cross-entropy beside the maps' L1, and of a present slot's beside an absent
#: one's (about 250 slots are absent for each present).
PRESENCE_WEIGHT, PRESENT_WEIGHT = 1.0, 20.0
#: The weight, in matching only, of the distance from a slot's anchor to a true map's shift (plane units).
ANCHOR_WEIGHT = 1.0
#: The attractor's box in training pairs, as `benchmarks/literature.py` frames its targets (EXTENT).
EXTENT = 0.75
#: Chaos-game chains and steps for a training image: 60,000 points (odds by area) cover a 64-pixel picture of ten maps.
CHAINS, STEPS, BURN_IN = 500, 120, 30
#: The numbers of maps training pairs draw (inclusive).
MAPS = (2, 10)
#: Seeds of training and validation pairs: ``default_rng([TAG, i])``, a stream apart from every integer seed that
#: the benchmarks draw (development 0-9, held out 1000+).
TRAIN_TAG, VALIDATION_TAG = 65, 66

#: Training: Adam's learning rate (cosine to 0), batch, steps and pool of pairs (redrawn each epoch by the
#: frame's 8 symmetries). More steps fit better and take longer: 2 idle CPU cores run 6-7 steps a second.
LR = 1e-3
BATCH = 64
TRAIN_STEPS = 12_000
POOL = 40_000
VALIDATION = 512
