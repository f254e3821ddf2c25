"""Bad input to the package's Python API, counted per class: clear / traceback / silent /
hang / recovered (as ``tools/fuzz_cli.py`` counts the command line's).

Run from the checkout (``MUJOCO_GL=egl .venv/bin/python tools/fuzz_api.py``; a minute). Each
case calls the API in this process with input a careless user or an attacker could give:

* *clear*: the expected error: a ``ValueError`` or ``TypeError`` whose message names what was
  wrong (the case's word: the argument or field);
* *traceback*: any other exception, or one whose message does not name it (a numpy or Python
  internals message, an ``AttributeError``);
* *silent*: no error where one was due (the input accepted, converted or truncated);
* *hang*: no return within :data:`TIMEOUT` seconds;
* *recovered*: valid input at an edge, answered honestly (an action accepted unchanged, a
  distractor clear of the robot accepted).

The class "world: DockingEnv's arguments" holds the cases of ``docking.world``, whose checks
(issue 49) are named in ``fingerprint.UNKEYED``. Prints one line per case and the counts;
exits 1 if any case is silent, a traceback or a hang.
"""

from __future__ import annotations

import dataclasses
import signal
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import gymnasium  # noqa: E402

import docking.gym_ids  # noqa: E402, F401  (registers the ids)
from docking.camera import CameraConfig  # noqa: E402
from docking.experiments import Curriculum, ExperimentConfig  # noqa: E402
from docking.network import NetworkConfig  # noqa: E402
from docking.presets import EXPERIMENT_1, EXPERIMENT_2, FLOOR_WORLD, NAO_WORLD  # noqa: E402
from docking.protocol import heldout_log  # noqa: E402
from docking.scene import Distractor, WorldConfig  # noqa: E402
from docking.study.contest import Knob, Ladder, contest, small_budget  # noqa: E402
from docking.study.sweep import grid_configs, parse_seeds  # noqa: E402

#: Three count fields of ExperimentConfig: 200 values each make a grid of 8 million.
_THREE_COUNTS = ("train_trials", "test_trials", "heldout_trials")

#: Seconds after which a case counts as a hang.
TIMEOUT = 60
KINDS = ("clear", "traceback", "silent", "hang", "recovered")


class _Timeout(BaseException):
    pass


def _alarm(signum, frame):
    raise _Timeout


def classify(call, names: str | None) -> tuple[str, str]:
    """``(kind, what happened)`` of ``call()``; ``names`` the word a clear error names, or
    None for valid input (recovered if it returns)."""
    signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(TIMEOUT)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = call()
    except _Timeout:
        return "hang", f"no return after {TIMEOUT} s"
    except (ValueError, TypeError) as exc:
        text = f"{type(exc).__name__}: {exc}".splitlines()[0]
        if names is not None and names in str(exc):
            return "clear", text
        return "traceback", text  # valid input refused, or an error that names nothing
    except Exception as exc:  # noqa: BLE001 - every other exception is what we count
        return "traceback", f"{type(exc).__name__}: {exc}".splitlines()[0]
    finally:
        signal.alarm(0)
    if names is None:
        return "recovered", f"returned {str(result)[:100]}"
    return "silent", f"returned {str(result)[:100]}"


def _continuous():
    env = gymnasium.make("docking/Continuous-v0", seed=0)
    env.reset(seed=0)
    return env


def _discrete():
    env = gymnasium.make("docking/Docking-v0", seed=0)
    env.reset(seed=0)
    return env


def _same_as_the_adapter(action):
    """A valid continuous action: gym.make's env and the adapter walk the same episode."""
    from docking.gym import DockingGymEnv

    made = gymnasium.make("docking/Continuous-v0", seed=5).unwrapped
    plain = DockingGymEnv(seed=5, preset="continuous")
    made.reset(seed=5), plain.reset(seed=5)
    a, b = made.step(action), plain.step(action)
    if not (np.array_equal(a[0], b[0]) and np.array_equal(a[4]["pose"], b[4]["pose"])):
        raise RuntimeError("the checked env walked another episode")
    return a[4]["pose"]


def _refused_then_usable(**bad):
    """``reset(**bad)`` as the first reset of a made env, then a valid ``reset(seed=0)`` and
    ``step(2)``: the refusal raised again if the env is still usable after it, else what the
    valid calls raised (a traceback); returns if ``bad`` is accepted (silent)."""
    env = gymnasium.make("docking/Docking-v0")
    try:
        env.reset(**bad)
    except (ValueError, TypeError) as refused:
        try:
            env.reset(seed=0)
            env.step(2)
        except Exception as exc:  # noqa: BLE001 - the env is unusable: counted as such
            raise RuntimeError(f"unusable after a refused reset: {exc!r}") from exc
        raise refused from None
    return "accepted"


@dataclasses.dataclass(frozen=True)
class FuzzedLearner:
    """A learner's configuration, for the registration cases (never run)."""

    name: str = "fuzzed"
    world: WorldConfig = WorldConfig()
    heldout_trials: int = 3
    train_trials: int = 2


def _learner_run(config, seed, progress=True, on_trials=None):
    raise RuntimeError("the registration cases never run a learner")


def _register(config_type=FuzzedLearner, **options):
    from docking.study import learners

    return learners.register(config_type, _learner_run, **options)


def _with(field: str, value) -> type:
    """:class:`FuzzedLearner` with ``field``'s default ``value``."""
    return dataclasses.make_dataclass(
        "FuzzedLearner", [(field, type(value), value)], bases=(FuzzedLearner,), frozen=True
    )


def _registration_cases() -> list:
    """Issue 60: register's arguments checked at registration; the command beside a number
    (verify_command) and the cells it names (cell_runs)."""
    from docking.study.design import cell_runs
    from docking.study.designs import replication
    from docking.study.report import verify_command

    return [
        (
            "register(libraries=('nosuchlib',))",
            lambda: _register(libraries=("nosuchlib",)),
            "nosuchlib",
        ),
        (
            "register(libraries=('yaml',)) (a module)",
            lambda: _register(libraries=("yaml",)),
            "PyYAML",
        ),
        ("register(libraries='scipy')", lambda: _register(libraries="scipy"), "libraries"),
        ("register(trials=5)", lambda: _register(trials=5), "trials"),
        ("register(trials=lambda c: -1)", lambda: _register(trials=lambda c: -1), "trials"),
        (
            "register(heldout_trials=-1 default)",
            lambda: _register(_with("heldout_trials", -1)),
            "heldout_trials",
        ),
        (
            "register(train_trials=2.5 default)",
            lambda: _register(_with("train_trials", 2.5)),
            "train_trials",
        ),
        ("register(libraries=('scipy',))", lambda: _register(libraries=("scipy",)), None),
        ("verify_command('../x')", lambda: verify_command("../x"), "design"),
        ("verify_command(cells=[''])", lambda: verify_command("paper", [""]), "cells"),
        ("verify_command(seeds=[])", lambda: verify_command("paper", seeds=[]), "seeds"),
        ("verify_command(seeds='7100')", lambda: verify_command("paper", seeds="7100"), "seeds"),
        ("verify_command(seeds=[-1])", lambda: verify_command("paper", seeds=[-1]), "seeds"),
        (
            "verify_command('paper', 'experiment1', range(5))",
            lambda: verify_command("paper", "experiment1", range(5)),
            None,
        ),
        (
            "cell_runs(replication, 'floor/papr')",
            lambda: cell_runs(replication.DESIGN, "floor/papr"),
            "floor/papr",
        ),
        (
            "cell_runs(replication, 'floor/paper', [7000])",
            lambda: cell_runs(replication.DESIGN, "floor/paper", [7000]),
            "7000",
        ),
        ("cell_runs('paper')", lambda: cell_runs("paper"), "design"),
    ]


def cases() -> dict[str, list]:
    """``{class: [(label, call, names)]}``: ``names`` None for valid input."""
    found: dict[str, list] = {}
    found["registering a learner, the runs behind a number"] = _registration_cases()
    bad_vectors = {
        "strings": ["0.5", "0.5"],
        "bools": np.ones(2, bool),
        "complex": np.full(2, 0.5 + 0.5j),
        "a bool list": [True, False],
        "mixed": [0.5, "x"],
        "ragged": [[0.5], [0.5, 1.0]],
        "None": None,
        "a dict": {"forward": 0.5},
        "nan": [np.nan, 0.0],
        "inf": [np.inf, 0.0],
        "beyond 1": [2.0, 0.0],
        "three numbers": [0.1, 0.2, 0.3],
        "a scalar": 0.5,
        "an object array": np.array([0.5, None], dtype=object),
        "bytes": b"\x00\x01",
    }
    found["gymnasium: Continuous-v0 actions"] = [
        (f"step({what})", lambda a=a: _continuous().step(a), "action")
        for what, a in bad_vectors.items()
    ] + [
        (f"step({a!r}) as the adapter", lambda a=a: _same_as_the_adapter(a), None)
        for a in ([0.5, -0.25], np.array([1, 0]), np.float32([0.1, 0.9]), (1.0, -1.0))
    ]
    found["gymnasium: discrete actions"] = [
        (f"step({what})", lambda a=a: _discrete().step(a), "action")
        for what, a in {**bad_vectors, "a float": 1.0, "True": True, "4": 4, "-1": -1}.items()
    ]
    found["gymnasium: make's arguments"] = [
        (f"make(seed={s!r})", lambda s=s: gymnasium.make("docking/Docking-v0", seed=s), "seed")
        for s in (True, False, 1.0, "1", -1, 2**40, [1], np.float64(2))
    ] + [
        (
            "make(seed=np.int64(3))",
            lambda: gymnasium.make("docking/Docking-v0", seed=np.int64(3)),
            None,
        ),
        (
            "make(colour='red')",
            lambda: gymnasium.make("docking/Docking-v0", colour="red"),
            "colour",
        ),
        (
            "make(camera={'tilt': 1})",
            lambda: gymnasium.make("docking/Docking-v0", camera={"tilt": 1}),
            "tilt",
        ),
        ("make(camera=3)", lambda: gymnasium.make("docking/Docking-v0", camera=3), "camera"),
        (  # gymnasium's own: a window of the rgb_array frames (HumanRendering)
            "make(render_mode='human')",
            lambda: gymnasium.make("docking/Docking-v0", render_mode="human"),
            None,
        ),
        (
            "make(render_mode='ansi')",
            lambda: gymnasium.make("docking/Docking-v0", render_mode="ansi"),
            "render_mode",
        ),
        ("make(preset=...)", lambda: gymnasium.make("docking/Docking-v0", preset="moon"), "preset"),
        (
            "make(max_steps=0)",
            lambda: gymnasium.make("docking/Docking-v0", max_steps=0),
            "max_steps",
        ),
        ("reset(seed=True)", lambda: _discrete().reset(seed=True), "seed"),
        ("reset(seed=-5)", lambda: _discrete().reset(seed=-5), "seed"),
        (
            "make(observation='image')",
            lambda: gymnasium.make("docking/Docking-v0", observation="image"),
            "observation",
        ),
    ]
    # Issue 52: each refused as the env's first reset, and the env usable after it.
    found["gymnasium: a refused reset"] = [
        (
            f"reset({k}={v!r}), then reset(seed=0); step(2)",
            lambda k=k, v=v: _refused_then_usable(**{k: v}),
            k,
        )
        for k, v in (
            ("seed", "0"),
            ("seed", 1.5),
            ("options", "abc"),
            ("options", ["start"]),
            ("options", {"start": [0, 0, 0]}),
        )
    ]
    found["seeds and grids"] = (
        [
            (f"parse_seeds({t!r})", lambda t=t: parse_seeds(t), "seeds")
            for t in (
                "1_0",
                "\u0661",
                "\u0663-5",
                "\uff11",
                "+1",
                "1e3",
                "0,0",
                "5-2",
                "-1",
                "",
                "0x1",
                "1.0",
            )
        ]
        + [
            ("parse_seeds('0-2, 7 9')", lambda: parse_seeds("0-2, 7 9"), None),
        ]
        + [
            (f"grid_configs({g})", lambda g=g: grid_configs(EXPERIMENT_1, g), "grid")
            for g in (
                ["network.eps_w=0,0.0"],
                ["network.eps_w=0.05,0.05"],
                ["network.eps_w=0", "network.eps-w=1"],
                ["world.heading_hold=true,yes"],
                ["train_trials=10,010"],
            )
        ]
        + [  # issue 52: numbers as the command line reads them (the error names the field)
            (f"grid_configs({g})", lambda g=g: grid_configs(EXPERIMENT_1, g), field)
            for g, field in (
                (["train_trials=1_0,20"], "train_trials"),
                (["network.eps_w=0.0_5"], "eps_w"),
                (["train_trials=\u0661\u0660"], "train_trials"),
            )
        ]
        + [
            (
                "grid_configs(8 million configurations: 200 x 200 x 200)",
                lambda: grid_configs(
                    EXPERIMENT_1,
                    [f"{f}={','.join(map(str, range(1, 201)))}" for f in _THREE_COUNTS],
                ),
                "grid",
            )
        ]
        + [
            (
                "grid_configs(two values)",
                lambda: grid_configs(EXPERIMENT_1, ["network.eps_w=0,0.05"]),
                None,
            ),
        ]
    )
    rows = Knob("train_trials", Ladder((100, 200, 500), 0, integer=True))
    cols = Knob("eval_trials", Ladder((1, 2, 5), 0, integer=True))
    found["contest and judging"] = [
        (f"contest({what})", lambda a=args: contest(*a, small_budget(rows=2, cols=2)), names)
        for what, args, names in (
            ("None, ...", (None, rows, cols), "learner"),
            ("ExperimentConfig (the class), ...", (ExperimentConfig, rows, cols), "learner"),
            ("learner, 'ab', 'cd'", (EXPERIMENT_2, "ab", "cd"), "rows"),
            ("learner, rows, 3", (EXPERIMENT_2, rows, 3), "cols"),
            ("lambda: config, ...", (lambda: EXPERIMENT_2, rows, cols), "learner"),
            ("lambda world, **s: 3, ...", (lambda world, **s: 3, rows, cols), "learner"),
            (
                "lambda world: config (takes no knob), ...",
                (lambda w: dataclasses.replace(EXPERIMENT_2, world=w), rows, cols),
                "learner",
            ),
            ("both knobs one field", (EXPERIMENT_2, rows, rows), "rows"),
            (
                "a knob naming no field",
                (EXPERIMENT_2, rows, Knob("nope", Ladder((1, 2, 5), 0))),
                "nope",
            ),
        )
    ] + [
        (
            f"heldout_log(policy returning {a!r})",
            lambda w=w, a=a: heldout_log(w, 0, 1, lambda observation, env: a),
            "your policy returned",
        )
        for w, a in (
            (WorldConfig(), 1.5),
            (WorldConfig(), "0"),
            (WorldConfig(), 4),
            (WorldConfig(actions="continuous"), [2.0, 0.0]),
        )
    ]
    found["configurations"] = (
        [
            (
                f"ExperimentConfig(heldout_world={v!r:.30})",
                lambda v=v: dataclasses.replace(EXPERIMENT_2, heldout_world=v),
                "heldout_world",
            )
            for v in (1, "x", {}, [], CameraConfig(), NetworkConfig(), EXPERIMENT_1)
        ]
        + [
            (
                f"ExperimentConfig(before={v!r:.30})",
                lambda v=v: dataclasses.replace(EXPERIMENT_2, before=v),
                "before",
            )
            for v in (1, "x", WorldConfig())
        ]
        + [
            (
                f"ExperimentConfig({f}={v!r:.30})",
                lambda f=f, v=v: dataclasses.replace(EXPERIMENT_2, **{f: v}),
                f,
            )
            for f, v in (
                ("world", None),
                ("network", "x"),
                ("curriculum", 3),
                ("train_trials", True),
                ("name", "../x"),
            )
        ]
        + [
            (
                "Curriculum(far_initial=nan)",
                lambda: Curriculum(far_initial=float("nan")),
                "far_initial",
            ),
        ]
    )
    start = dataclasses.replace(EXPERIMENT_2.world, start_near=0.8)
    found["worlds: distractors"] = (
        [
            (what, lambda d=d: dataclasses.replace(start, distractors=(d,)), "distractors")
            for what, d in {
                "a 2 m box over the start region": Distractor(
                    "box", (1.0, 1.0, 1.0), (-1.0, 0.0, 1.0)
                ),
                "a box on the dock": Distractor("box", (0.04, 0.04, 0.04), (-0.48, 0.0, 0.04)),
                "a sphere 3 cm beside the start region": Distractor(
                    "sphere", (0.05,), (-1.0, 0.3, 0.05)
                ),
                "a cylinder beside the dock": Distractor(
                    "cylinder", (0.05, 0.3), (-0.48, 0.18, 0.3)
                ),
                "a sphere over the start region, high": Distractor(
                    "sphere", (0.1,), (-1.2, 0.0, 0.9)
                ),
            }.items()
        ]
        + [
            (what, lambda w=w, d=d: dataclasses.replace(w, distractors=(d,)), None)
            for what, w, d in (
                ("the cup on the sideboard", WorldConfig(), Distractor.cup(0.3)),
                ("the cup in Experiment 2", EXPERIMENT_2.world, Distractor.cup(-0.3)),
                ("the cup in the Nao world", NAO_WORLD, Distractor.cup(0.3)),
                (
                    "the cup on the floor",
                    FLOOR_WORLD,
                    Distractor("cylinder", (0.035, 0.045), (0.03, 0.3, 0.045)),
                ),
                (
                    "a sphere 0.25 m beside the start region",
                    start,
                    Distractor("sphere", (0.05,), (-1.0, 0.5, 0.05)),
                ),
            )
        ]
        + [
            ("WorldConfig(distractors=[1])", lambda: WorldConfig(distractors=[1]), "distractors"),
            ("Distractor('box', (1,), ...)", lambda: Distractor("box", (1,), (0, 0, 0)), "size"),
            ("Distractor('cone', ...)", lambda: Distractor("cone", (0.1,), (0, 0, 0)), "shape"),
            (
                "Distractor(position=(nan, 0, 0))",
                lambda: Distractor("sphere", (0.1,), (float("nan"), 0, 0)),
                "position",
            ),
        ]
    )
    env = _world_env()
    found["world: DockingEnv's arguments"] = [
        ("reset_to([-100, 0, 0]) (outside the room)", lambda: env.reset_to([-100, 0, 0]), "pose"),
        ("reset_to([0, 50, 0]) (outside the room)", lambda: env.reset_to([0, 50, 0]), "pose"),
        ("reset_to([-1, 0, 1e308]) (a yaw)", lambda: env.reset_to([-1, 0, 1e308]), "pose"),
        ("reset_to([-1, 0, inf])", lambda: env.reset_to([-1, 0, np.inf]), "pose"),
        ("reset_to([nan, 0, 0])", lambda: env.reset_to([np.nan, 0, 0]), "pose"),
        ("reset_to('abc')", lambda: env.reset_to("abc"), "pose"),
        ("landmark_in_crop(margin=nan)", lambda: env.landmark_in_crop(margin=np.nan), "margin"),
        (
            "landmark_in_crop(pose=[nan, 0, 0])",
            lambda: env.landmark_in_crop(pose=[np.nan, 0, 0]),
            "pose",
        ),
        ("landmark_in_crop(margin='a')", lambda: env.landmark_in_crop(margin="a"), "margin"),
        ("landmark_in_crop(pose='abc')", lambda: env.landmark_in_crop(pose="abc"), "pose"),
        ("DockingEnv.step('0')", lambda: env.step("0"), "action"),
        ("DockingEnv(seed=True)", lambda: type(env)(WorldConfig(), seed=True), "seed"),
        ("DockingEnv(config='sideboard')", lambda: type(env)(config="sideboard"), "config"),
        ("DockingEnv(config={})", lambda: type(env)(config={}), "config"),
        ("DockingEnv(CameraConfig())", lambda: type(env)(CameraConfig()), "config"),
        (
            "reset_to([-1, 0.2, 6 pi]) (three turns)",
            lambda: env.reset_to([-1, 0.2, 6 * np.pi]),
            None,
        ),
        (
            "landmark_in_crop([-1, 0, 0], margin=0)",
            lambda: env.landmark_in_crop([-1, 0, 0], 0),
            None,
        ),
    ]
    return found


def _world_env():
    from docking.world import DockingEnv

    env = DockingEnv(WorldConfig(), seed=0)
    env.reset()
    return env


def main() -> int:
    totals: dict[str, dict[str, int]] = {}
    for name, found in cases().items():
        counts = totals.setdefault(name, dict.fromkeys(KINDS, 0))
        print(f"== {name}", flush=True)
        for label, call, names in found:
            kind, said = classify(call, names)
            counts[kind] += 1
            print(f"{kind:9s} {label}\n          {said[:150]}", flush=True)
    print("\nclass: clear / traceback / silent / hang / recovered")
    for name, counts in totals.items():
        print(f"{name}: " + " / ".join(str(counts[k]) for k in KINDS))
    bad = sum(c[k] for c in totals.values() for k in ("traceback", "silent", "hang"))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
