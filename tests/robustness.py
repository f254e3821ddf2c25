"""Bad input and faults, counted (issue 17): ``python tests/robustness.py [--cli]``.

Not a pytest module (the unit tests check each class once; this tries many cases of each and
counts the outcomes). Every case ends as one of

* ``clear``: refused with an error that names the field, option, file or address at fault;
* ``recovered``: a bad stored file that is ignored with a warning and recomputed;
* ``silent``: accepted, or a wrong result served without a word (must be 0);
* ``crash``: an error that names nothing, or a traceback from the CLI (must be 0).
"""

from __future__ import annotations

import collections
import dataclasses
import io
import subprocess
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from docking.experiments import Curriculum  # noqa: E402
from docking.network import Network, NetworkConfig  # noqa: E402
from docking.presets import EXPERIMENT_1  # noqa: E402
from docking.study.kinds import (  # noqa: E402
    CorruptResult,
    content_digest,
    load_result,
    result_arrays,
    result_path,
    run_key,
)
from docking.study.store import run_or_load  # noqa: E402
from docking.world import DockingEnv, WorldConfig  # noqa: E402

TINY = dataclasses.replace(
    EXPERIMENT_1, name="fuzz", train_trials=3, test_trials=2, eval_every=3, eval_trials=1
)
BAD_VALUES = [
    -1,
    0,
    -1e-9,
    10**400,
    1e300,
    -1e300,
    float("nan"),
    float("inf"),
    True,
    "1",
    None,
    [1],
]
counts: dict[str, collections.Counter] = collections.defaultdict(collections.Counter)
silent: list[str] = []


def expect_refusal(kind: str, what: str, call, names: str) -> None:
    """``call()`` must raise an error whose message contains ``names``."""
    try:
        call()
    except (ValueError, TypeError, RuntimeError, OSError, LookupError) as exc:
        counts[kind]["clear" if names in str(exc) else "crash"] += 1
        if names not in str(exc):
            print(f"  unclear: {what}: {type(exc).__name__}: {exc}")
        return
    except Exception as exc:  # noqa: BLE001 - counted, not hidden
        counts[kind]["crash"] += 1
        print(f"  crash: {what}: {type(exc).__name__}: {exc}")
        return
    counts[kind]["accepted"] += 1


def config_fields() -> None:
    for cls, owner in ((NetworkConfig, "NetworkConfig"), (WorldConfig, "WorldConfig")):
        for field in dataclasses.fields(cls):
            if field.name in ("camera", "distractors", "scene", "actions", "rule", "feature_layer"):
                continue
            for value in BAD_VALUES:
                what = f"{owner}({field.name}={value!r})"
                before = counts["config"]["accepted"]
                expect_refusal(
                    "config", what, lambda c=cls, f=field.name, v=value: c(**{f: v}), field.name
                )
                if counts["config"]["accepted"] > before:
                    counts["config"]["accepted"] -= 1
                    counts["config"]["valid value"] += 1  # e.g. 0 steps of noise: allowed
    for field in ("train_trials", "test_trials", "eval_every", "heldout_trials"):
        for value in (-1, 10**30, 1.5, True, "3"):
            expect_refusal(
                "config",
                f"ExperimentConfig({field}={value!r})",
                lambda f=field, v=value: dataclasses.replace(TINY, **{f: v}),
                field,
            )
    for value in (-1, 1.5, 10**30):
        expect_refusal(
            "config",
            f"Curriculum(grow_trials={value})",
            lambda v=value: Curriculum(1, v, 1),
            "grow",
        )
    # config.json read back (ExperimentConfig.from_dict): every wrong shape a TypeError
    from docking.experiments import ExperimentConfig

    good = TINY.to_dict()
    for what, d, names in (
        ("an unknown field", {**good, "nope": 1}, "nope"),
        ("no world", {k: v for k, v in good.items() if k != "world"}, "world"),
        ("world a list", {**good, "world": [1]}, "world"),
        ("network a string", {**good, "network": "x"}, "network"),
        ("camera unknown field", {**good, "world": {**good["world"], "camera": {"x": 1}}}, "x"),
        (
            "distractor a number",
            {**good, "world": {**good["world"], "distractors": [3]}},
            "distractors",
        ),
        ("curriculum empty", {**good, "curriculum": {}}, "far_initial"),
        ("not a dict", [good], "mapping"),
    ):
        expect_refusal(
            "config", f"from_dict({what})", lambda x=d: ExperimentConfig.from_dict(x), names
        )
    for field, value in (("dock_center", 1e300), ("dock_center", 5.0), ("view_margin_px", 100)):
        expect_refusal(
            "config",
            f"WorldConfig({field}={value})",
            lambda f=field, v=value: WorldConfig(**{f: v}),
            field,
        )
    for what, change, names in (
        ("a yardstick that trains", dict(policy="oracle"), "does not learn"),
        ("an unknown policy", dict(policy="ppo", train_trials=0, eval_trials=0), "policy"),
        ("an unknown pretraining rule", dict(pretrain_rule="kohonen"), "pretrain_rule"),
        ("no training for the learner", dict(train_trials=0), "train_trials"),
    ):
        expect_refusal("config", what, lambda c=change: dataclasses.replace(TINY, **c), names)
    expect_refusal(
        "config",
        "permute_delta with a constant",
        lambda: NetworkConfig(permute_delta=True, feature_delta=0.1),
        "permute_delta",
    )


def env_inputs() -> None:
    env = DockingEnv(seed=0)
    for pose in ([0, 0], None, [np.nan, 0, 0], "abc", [[1, 2, 3]], [1e309, 0, 0]):
        expect_refusal("env", f"reset_to({pose!r})", lambda p=pose: env.reset_to(p), "pose")
    for seed in (-1, True, 2**40, 1.5, "0"):
        expect_refusal(
            "env", f"DockingEnv(seed={seed!r})", lambda s=seed: DockingEnv(seed=s), "seed"
        )
    for w, h in ((0, 10), (10, -1), (10**6, 10), (1.5, 10)):
        expect_refusal(
            "env",
            f"render_view({w}, {h})",
            lambda a=w, b=h: env.render_view("top", a, b),
            "render_view",
        )
    for tries in (0, -3, 1.5):
        expect_refusal(
            "env", f"sample_start_pose({tries})", lambda t=tries: env.sample_start_pose(t), "tries"
        )
    net = Network(NetworkConfig(), np.random.default_rng(0))
    I = net.prepare(np.ones(320))
    for delta in (10**400, float("nan"), "x"):
        expect_refusal(
            "network",
            f"update(delta={delta!r})",
            lambda d=delta: net.update(I, net.features(I), 0, d),
            "delta",
        )


def stored_files() -> None:
    """Byte flips, truncation, another run's file, edited arrays: never served."""
    with tempfile.TemporaryDirectory() as tmp:
        for seed in (0, 1):
            run_or_load(TINY, seed, tmp, progress=False)
        good = result_path(TINY, 0, tmp).read_bytes()
        good_digest = content_digest(result_arrays(load_result(result_path(TINY, 0, tmp))))
        other = result_path(TINY, 1, tmp).read_bytes()
        rng = np.random.default_rng(0)
        cases = [("another run's file", other)]
        for k in range(40):
            data = bytearray(good)
            for _ in range(1 + k % 4):
                data[int(rng.integers(len(data)))] ^= 1 << int(rng.integers(8))
            cases.append((f"bit flips {k}", bytes(data)))
        cases += [(f"truncated to {n}", good[:n]) for n in (0, 10, len(good) // 2, len(good) - 1)]
        with np.load(io.BytesIO(good)) as f:
            arrays = {n: f[n] for n in f.files}
        for name, change in (
            ("inverted test.success", lambda a: a.__setitem__("test.success", ~a["test.success"])),
            ("NaN pose", lambda a: a["test.poses"].__setitem__((0, 0), np.nan)),
            ("Q = 1e308", lambda a: a["Q"].__setitem__((0, 0), 1e308)),
            ("a dropped array", lambda a: a.pop("train.deltas")),
        ):
            edited = {n: v.copy() for n, v in arrays.items()}
            change(edited)
            buffer = io.BytesIO()
            np.savez_compressed(buffer, **edited)
            cases.append((name, buffer.getvalue()))
        path = result_path(TINY, 0, tmp)
        for what, data in cases:
            path.write_bytes(data)
            try:
                served = load_result(path, run_key(TINY, 0))
            except CorruptResult:
                pass
            else:  # the flip missed every array (zip metadata): the same run, harmless
                same = content_digest(result_arrays(served)) == good_digest
                counts["store"]["unchanged content" if same else "silent"] += 1
                if not same:
                    silent.append(what)
                continue
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                result = run_or_load(TINY, 0, tmp, progress=False)
            ok = result.seed == 0 and path.read_bytes() != data
            counts["store"]["recovered" if ok and caught else "silent"] += 1
            if not (ok and caught):
                silent.append(what)


def cli() -> None:
    cases = [
        (["run", "experiment1", "--seeds", "5-2"], "seeds"),
        (["run", "experiment1", "--seeds", "0-9999999"], "seeds"),
        (["run", "experiment1", "--seeds", "-3"], "seeds"),
        (["run", "experiment1", "--network.eps-q", "1e300"], "eps_q"),
        (["run", "experiment1", "--network.beta-s", "1" + "0" * 400], "beta_s"),
        (["run", "experiment1", "--world.view-margin-px", "100"], "view_margin_px"),
        (["run", "experiment1", "--train-trials", "1" + "0" * 30], "train_trials"),
        (["run", "experiment1", "--seeds", "0", "--scheduler", "http://127.0.0.1:1"], "HOST:PORT"),
        (
            ["run", "experiment1", "--seeds", "7777", "--scheduler", "tcp://127.0.0.1:1"],
            "127.0.0.1:1",
        ),
        (["sweep", "experiment1", "--grid", "network.nope=1"], "nope"),
        (["sweep", "experiment1", "--grid", "network.eps_w"], "grid"),
        (["verify", "--sample", "-1"], "--sample"),
        (["benchmark", "--steps", "-5"], "--steps"),
        (["benchmark", "--repeats", "0"], "--repeats"),
        (["run", "experiment1", "--results-dir", "/proc/forbidden"], "/proc/forbidden"),
        (["run", "experiment1", "--world.scene", "flor"], "scene"),
        (["run", "experiment1", "--network.rule", "nonlcal"], "rule"),
        (["design", "run", "nosuch"], "nosuch"),
        (["design", "run", "experiment3", "--seeds", "5-2"], "seeds"),
        (["design", "run", "experiment3", "--scheduler", "tcp://127.0.0.1:1"], "127.0.0.1:1"),
        (["ledger", "update", "--results-dir", "/nonexistent/store"], "/nonexistent/store"),
    ]
    for args, names in cases:
        found = subprocess.run(
            [sys.executable, "-m", "docking", *args],
            cwd=ROOT,
            capture_output=True,
            text=True,
            timeout=120,
            env={**__import__("os").environ, "DOCKING_LEDGER": "off"},
        )
        tb = "Traceback" in found.stderr
        kind = "clear" if found.returncode and names in found.stderr and not tb else "crash"
        if found.returncode == 0:
            kind = "accepted"
        counts["cli"][kind] += 1
        if kind != "clear":
            print(f"  {kind}: {' '.join(args)}: {found.stderr[-300:]}")


if __name__ == "__main__":
    config_fields()
    env_inputs()
    stored_files()
    if "--cli" in sys.argv:
        cli()
    for kind, c in counts.items():
        print(f"{kind:8s} " + ", ".join(f"{k}: {v}" for k, v in sorted(c.items())))
    print("silent wrong results:", silent or 0)
    sys.exit(1 if silent or any(c["crash"] for c in counts.values()) else 0)
