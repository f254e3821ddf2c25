"""The package's figures, drawn from arrays: this subpackage draws and does nothing else.

* :func:`fig2_scene` -- Fig. 2: the scene, the robot's camera view with the crop rectangle, the
  32x10 input; plus the views from the left of, in front of and to the right of the landmark.
* :func:`fig3` -- Fig. 3: Experiment 1's raw views, action and feature receptive fields.
* :func:`fig4` -- Fig. 4: Experiment 2's action and feature receptive fields, the feature
  units that contribute most to L, R and F framed in red.
* :func:`fig5` -- Fig. 5: sample test trajectories seen from above.
* :func:`fig_learning_curves` -- test success and steps during training (not in the paper).

The paper's figures are :mod:`docking.study.figures.paper`, the study's (Experiment 3, the
contest, the verdicts, the first screen, an episode's animation) :mod:`docking.study.figures.study`,
and what they share (saving, layout, colours, the floor plan)
:mod:`docking.study.figures.common`; every figure function is importable from here.

Every figure function takes arrays (what :mod:`docking.study.arrays`,
:mod:`docking.study.analysis` or :mod:`docking.study.episodes` computes; the floor plan a path
is drawn on is :func:`docking.study.analysis.floor_plan`'s, passed in), and configurations
for labels, and returns a :class:`matplotlib.figure.Figure`; it renders nothing, runs no
network and writes no file, and imports neither the world, the renderer, the runs' code nor
:mod:`docking.study.analysis` (an import contract of ``pyproject.toml``).
Panels are laid out by matplotlib's constrained layout, grouped in subfigures, each headed by
its bold panel letter. The caller saves the figure with :func:`save_figure` (``.png`` and
``.pdf``). The figures are drawn on matplotlib's Agg canvas without pyplot, so the library
never opens a window.

Conventions, as in the paper's captions: "Strong weights are displayed dark" -- every weight
or input image uses a reversed gray colormap (white = 0), without interpolation and with square
pixels, so a 32x10 field looks 32x10. Each receptive field is scaled from 0 to its own maximum
(written under it, so a weak field is not mistaken for a strong one; negative values, if any,
show white); network inputs use the fixed scale 0..1. Action fields are shown in the paper's
order L, R, F, B.
"""

from docking.study.figures import common, paper, study
from docking.study.figures.common import (
    FIGURES_DIR,
    PAPER_ACTION_ORDER,
    action_order,
    draw_floor_plan,
    draw_trajectory,
    save_figure,
    to_png,
)
from docking.study.figures.paper import (
    fig2_scene,
    fig3,
    fig4,
    fig5,
    fig_learning_curves,
    fig_rewards,
    fig_trial,
)
from docking.study.figures.study import (
    episode_images,
    fig_action_fields,
    fig_claims,
    fig_contest,
    fig_coping,
    fig_decomposition,
    fig_experiment3,
    fig_failure_matrix,
    fig_glance,
    fig_landscape,
    fig_verdicts,
    save_gif,
)

__all__ = [
    "FIGURES_DIR",
    "PAPER_ACTION_ORDER",
    "action_order",
    "common",
    "draw_floor_plan",
    "draw_trajectory",
    "episode_images",
    "fig2_scene",
    "fig3",
    "fig4",
    "fig5",
    "fig_action_fields",
    "fig_claims",
    "fig_contest",
    "fig_coping",
    "fig_decomposition",
    "fig_experiment3",
    "fig_failure_matrix",
    "fig_glance",
    "fig_landscape",
    "fig_learning_curves",
    "fig_rewards",
    "fig_trial",
    "fig_verdicts",
    "paper",
    "save_figure",
    "save_gif",
    "study",
    "to_png",
]
