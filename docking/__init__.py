"""docking: a reproduction of Kleesiek, Weber, Wermter & Engel (2011) on dm-control.

"Reward-Driven Learning of Sensorimotor Laws and Visual Features" (IEEE ICDL-EpiRob 2011):
a robot learns to dock from 32x10 camera pixels with a two-layer network (softmax feature
layer -> Q-value action layer) trained by SARSA, where the same TD error delta also trains
the visual features (Eq. 8).
"""

__version__ = "0.1.0"
