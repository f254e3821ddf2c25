"""What a stored run of each built-in kind holds, and how it is read back: the layouts of a
trial log and of a learning curve, one array read with its size checked before it is
decompressed (:func:`array`), a trial log checked against its configuration
(:func:`trial_log`); per kind (the paper's learner, PPO) the arrays its file stores
(:func:`result_arrays`; PPO's is :func:`docking.study.ppo.result_arrays`), its file's parser
and its ledger-table row's decoder (what :class:`docking.study.kinds.Runner` names as
``parse`` and ``from_table``). :mod:`docking.study.kinds` checks a file's meta record, key and
digest around them; a registered learner's are :mod:`docking.study.learners`'.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from docking.experiments import ExperimentConfig, ExperimentResult, TrialLog
from docking.network import Network

__all__ = [
    "CURVE_LAYOUT",
    "CorruptResult",
    "TRIAL_LOG_LAYOUT",
    "array",
    "expect_members",
    "learner_from_table",
    "member_size",
    "parse_learner",
    "parse_ppo",
    "ppo_from_table",
    "result_arrays",
    "trial_log",
]


class CorruptResult(ValueError):
    """A saved result that cannot be used: unreadable, incomplete or inconsistent."""


#: dtype kind and number of dimensions of every array in a result file.
TRIAL_LOG_LAYOUT = {
    "success": ("b", 1),
    "steps": ("i", 1),
    "start_far": ("f", 1),
    "poses": ("f", 2),
    "actions": ("i", 1),
    "winners": ("i", 1),
    "deltas": ("f", 1),
}


CURVE_LAYOUT = {
    "curve_trials": ("i", 1),
    "curve_success": ("f", 1),
    "curve_steps": ("f", 1),
    "curve_rewarded": ("i", 1),
}


def member_size(data, name: str) -> int:
    try:
        return data.zip.getinfo(f"{name}.npy").file_size
    except KeyError:
        raise CorruptResult(f"array {name!r} is missing") from None


def array(data, name: str, kind: str, ndim: int, limit: int) -> np.ndarray:
    """The array ``name``, checked to hold at most ``limit`` bytes of data *before* it is
    decompressed, then for its dtype kind and dimensions."""
    size = member_size(data, name)
    if size > limit + 4096:  # the .npy header is at most a few hundred bytes
        raise CorruptResult(f"array {name!r} would decompress to {size} bytes, at most {limit}")
    array = data[name]
    if array.dtype.kind != kind or array.ndim != ndim:
        raise CorruptResult(
            f"array {name!r} has dtype {array.dtype} and {array.ndim} dimensions, expected "
            f"kind {kind!r} and {ndim}"
        )
    if kind == "f" and name != "curve_steps" and not np.isfinite(array).all():
        raise CorruptResult(f"array {name!r} holds non-finite values")
    return array


def trial_log(data, part: str, expected_trials: int, max_steps: int) -> TrialLog:
    # Bytes an array of this part can hold at most: 8 per entry, 3 entries per pose, one pose
    # per action plus the start, at most max_steps actions per trial.
    per = {"poses": 24 * (max_steps + 1), "actions": 8 * max_steps, "winners": 8 * max_steps}
    per["deltas"] = 8 * max_steps
    fields = {
        name: array(data, f"{part}.{name}", kind, ndim, expected_trials * per.get(name, 8))
        for name, (kind, ndim) in TRIAL_LOG_LAYOUT.items()
    }
    log = TrialLog(**fields)
    n = len(log.success)
    if n != expected_trials:
        raise CorruptResult(f"{part} holds {n} trials, the configuration {expected_trials}")
    if len(log.steps) != n or len(log.start_far) != n:
        raise CorruptResult(f"{part}: per-trial arrays of different lengths")
    if np.any(log.steps < 1):
        raise CorruptResult(f"{part}: a trial with no action")
    actions = int(np.sum(log.steps))
    if log.poses.shape != (actions + n, 3):
        raise CorruptResult(
            f"{part}.poses has shape {log.poses.shape}, expected ({actions + n}, 3)"
        )
    for name in ("actions", "winners", "deltas"):
        if len(fields[name]) != actions:
            raise CorruptResult(
                f"{part}.{name} holds {len(fields[name])} steps, expected {actions}"
            )
    return log


def expect_members(data, expected: set[str]) -> None:
    if set(data.files) != expected:
        odd = sorted(set(data.files) ^ expected)
        raise CorruptResult(f"unexpected or missing arrays: {', '.join(odd)}")


def result_arrays(result: ExperimentResult) -> dict[str, np.ndarray]:
    """The arrays a stored run of the learner holds (all but its ``meta`` record), by name."""
    arrays = {
        "W": result.network.W,
        "Q": result.network.Q,
        "curve_trials": result.curve_trials,
        "curve_success": result.curve_success,
        "curve_steps": result.curve_steps,
        "curve_rewarded": result.curve_rewarded,
    }
    for part in ("train", "test", "heldout"):
        log = getattr(result, part)
        for field in dataclasses.fields(TrialLog) if log is not None else ():
            arrays[f"{part}.{field.name}"] = getattr(log, field.name)
    return arrays


def parse_learner(data, config: ExperimentConfig, seed: int, walls) -> ExperimentResult:
    """The learner's run of the file ``data`` (its meta record checked already)."""
    parts = ("train", "test") + (("heldout",) if config.heldout_trials else ())
    expected = {"meta", "W", "Q", *CURVE_LAYOUT}
    expected |= {f"{part}.{name}" for part in parts for name in TRIAL_LOG_LAYOUT}
    expect_members(data, expected)
    net = config.network
    W = array(data, "W", "f", 2, 8 * net.n_features * net.n_inputs)
    Q = array(data, "Q", "f", 2, 8 * net.n_actions * net.n_features)
    if W.shape != (net.n_features, net.n_inputs) or Q.shape != (net.n_actions, net.n_features):
        raise CorruptResult(f"W {W.shape} or Q {Q.shape} do not fit the network")
    points = 1 + config.train_trials // config.eval_every if config.eval_trials else 0
    curve = {
        name: array(data, name, kind, ndim, 8 * points)
        for name, (kind, ndim) in CURVE_LAYOUT.items()
    }
    if any(len(v) != points for v in curve.values()):
        raise CorruptResult(f"learning-curve arrays must hold {points} points")
    try:
        network = Network.from_weights(config.network, W, Q)
    except ValueError as exc:
        raise CorruptResult(str(exc)) from exc
    steps = config.world.max_steps
    logs = {
        "train": trial_log(data, "train", config.train_trials, steps),
        "test": trial_log(data, "test", config.test_trials, steps),
        "heldout": (
            trial_log(data, "heldout", config.heldout_trials, steps)
            if config.heldout_trials
            else None
        ),
    }
    return ExperimentResult(
        config=config,
        seed=seed,
        network=network,
        **logs,
        **curve,
        wall_time_train=walls[0],
        wall_time_test=walls[1],
    )


def parse_ppo(data, config, seed: int, walls):
    """PPO's run (a :class:`docking.study.ppo.PPOResult`) of the file ``data`` (its meta record
    checked already): its training episodes (at most one per environment step) and its
    held-out trial log."""
    from docking.study import ppo

    expected = {"meta", "train.success", "train.steps"}
    expected |= {f"heldout.{name}" for name in TRIAL_LOG_LAYOUT}
    expect_members(data, expected)
    success = array(data, "train.success", "b", 1, 8 * config.steps)
    steps = array(data, "train.steps", "i", 1, 8 * config.steps)
    if len(success) != len(steps):
        raise CorruptResult("train.success and train.steps hold different numbers of episodes")
    if np.any(steps < 1) or int(np.sum(steps)) > config.steps:
        raise CorruptResult(f"training episodes of more steps than the budget ({config.steps})")
    heldout = trial_log(data, "heldout", config.heldout_trials, config.world.max_steps)
    return ppo.PPOResult(
        config=config,
        seed=seed,
        train_success=success,
        train_steps=steps,
        heldout=heldout,
        wall_time_train=walls[0],
        wall_time_test=walls[1],
    )


def learner_from_table(config, seed: int, row: dict, logs: dict, walls) -> ExperimentResult:
    """The learner's run of a ledger table's ``row`` (its network where the row keeps W and Q)."""
    net = config.network
    network = None
    if "W" in row:
        W, Q = row["W"].reshape(net.n_features, -1), row["Q"].reshape(net.n_actions, -1)
        network = Network.from_weights(net, W, Q)
    return ExperimentResult(
        config,
        seed,
        network,
        logs["train"],
        logs["test"],
        *(row[f"curve_{c}"] for c in ("trials", "success", "steps", "rewarded")),
        *walls,
        heldout=logs["heldout"],
    )


def ppo_from_table(config, seed: int, row: dict, logs: dict, walls):
    """PPO's run of a ledger table's ``row``: its training episodes where the row keeps them,
    its held-out trial log."""
    from docking.study import ppo

    train = [row.get(f"train.{f}") for f in ("success", "steps")]
    return ppo.PPOResult(config, seed, *train, logs["heldout"], *walls)
