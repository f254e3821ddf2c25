"""The study layer: the machinery that asks the paper's questions of many runs.

The core (``docking/``'s top level: the world, the learner, a run) never imports this folder;
this folder builds on it. Here are the kinds of run and their keys, the results store and the
committed ledger (and the one path from a configuration and seed to its run,
:func:`docking.study.runs.locate`), sweeps on a Dask cluster, the designs and their claims,
statistics, the contest, the reports, the figures and the command line
(docs/guide/layers.md draws them).
"""
