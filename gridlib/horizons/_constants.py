"""Choices and limits shared by the surfaces modules."""

METHODS = ("linear", "cubic", "rbf", "nearest")
EXTRAPOLATIONS = ("nan", "nearest", "trend")
ORDERINGS = ("error", "erode", "onlap")
RBF_GLOBAL_MAX = 2000  # beyond this many points (per block) the RBF is local by default
RBF_NEIGHBORS = 64  # ... with this many neighbours
