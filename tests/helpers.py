"""Shared test fixtures' data: the tiny learner configuration and seeds that the ledger's
tests (tests/test_ledger.py, tests/test_fuzz_defects.py) build their stores and ledgers of."""

from __future__ import annotations

import dataclasses

from docking.presets import EXPERIMENT_1

#: A learner run of a few trials (seconds): what a tiny store and ledger hold.
TINY = dataclasses.replace(
    EXPERIMENT_1,
    name="tiny",
    train_trials=4,
    test_trials=6,
    eval_every=4,
    eval_trials=1,
    heldout_trials=5,
)
#: The seeds of a tiny store.
SEEDS = (0, 1)
