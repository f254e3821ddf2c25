"""Bad input is a clear error (issue #7): every config field, actions, network inputs,
run_trial's options, rendering backends. Property-based tests (hypothesis) for the network
and the configs."""

import dataclasses
import math
import os
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from docking.camera import CameraConfig
from docking.experiments import Curriculum, ExperimentConfig
from docking.network import Network, NetworkConfig
from docking.presets import EXPERIMENT_1
from docking.trial import run_trial
from docking.validate import FieldTypeError
from docking.world import DockingEnv, WorldConfig


# Values that are the wrong *type* for every numeric field.
class _Opaque:
    """An object that is no number, with a repr that is the same in every process (pytest-xdist
    needs the same test ids in each worker)."""

    def __repr__(self):
        return "<opaque>"


NOT_NUMBERS = [None, "1", b"1", True, False, np.bool_(True), 1j, [1], (1,), {}, _Opaque()]
NOT_FINITE = [math.nan, math.inf, -math.inf, np.float64("nan")]
NOT_INTEGERS = [2.5, 1.0, np.float64(3.0)]  # counts must be integers, also integral floats

# (config class, a valid instance's kwargs, {field: out-of-range values})
RANGES = {
    CameraConfig: {
        "width": [0, -1, 5000],
        "height": [0, -3, 5000],
        "fovy_deg": [0.0, -10.0, 180.0, 400.0],
        "tilt_deg": [-91.0, 90.5],
        "hue_tol": [-1, 91],
        "min_saturation": [-1, 256],
        "min_value": [-1, 300],
    },
    WorldConfig: {
        "step_forward": [0.0, -0.1, 1.5],
        "step_side": [0.0, -0.1, 2.0],
        "step_noise_xy": [-0.01, 0.6],
        "step_noise_yaw_deg": [-1.0, 91.0],
        "max_steps": [0, -5],
        "start_near": [0.0, -1.0, 0.2],
        "start_far": [0.0, 0.5, 5.0],
        "start_half_angle_deg": [-1.0, 45.0, 90.0],
        "start_yaw_deg": [-1.0, 95.0],
        "dock_center": [0.0, -0.5, 0.3],
        "dock_depth": [0.0, -0.08, 1.5],
        "dock_width": [0.0, -0.2, 3.0],
        "view_margin_px": [-1.0, 101.0],
    },
    NetworkConfig: {
        "n_inputs": [0, -1],
        "n_features": [0, -4, 10**7],
        "n_actions": [0],
        "beta_s": [0.0, -1.0],
        "beta_a_train": [0.0, -2.0],
        "beta_a_test": [0.0],
        "gamma": [-0.1, 1.1],
        "eps_q": [-0.1],
        "eps_w": [-0.05],
        "q_init": [-1.0],
    },
    Curriculum: {"far_initial": [0.0, -0.7], "grow_trials": [-1]},
}
INTEGER_FIELDS = {
    CameraConfig: {"width", "height", "hue_tol", "min_saturation", "min_value"},
    WorldConfig: {"max_steps"},
    NetworkConfig: {"n_inputs", "n_features", "n_actions"},
    Curriculum: {"grow_trials"},
}
DEFAULTS = {
    CameraConfig: {},
    WorldConfig: {},
    NetworkConfig: {},
    Curriculum: {"far_initial": 0.7, "grow_trials": 10},
}


def _bad_cases():
    cases = []
    for cls, ranges in RANGES.items():
        for field, out_of_range in ranges.items():
            cases += [(cls, field, v, FieldTypeError) for v in NOT_NUMBERS]
            cases += [(cls, field, v, ValueError) for v in out_of_range]
            if field in INTEGER_FIELDS[cls]:
                cases += [(cls, field, v, FieldTypeError) for v in NOT_INTEGERS + NOT_FINITE]
            else:
                cases += [(cls, field, v, ValueError) for v in NOT_FINITE]
    # Fields that are not numbers.
    cases += [(NetworkConfig, "rule", v, ValueError) for v in ("Local", "", "hebbian")]
    cases += [(NetworkConfig, "rule", v, FieldTypeError) for v in (None, 1, True, ["local"])]
    cases += [(NetworkConfig, "normalize_input", v, FieldTypeError) for v in (1, 0, "yes", None)]
    cases += [(CameraConfig, "crop", v, ValueError) for v in ((0, 0, 0, 0), (0, 80, 160, 60))]
    cases += [(CameraConfig, "crop", v, FieldTypeError) for v in ((0, 16, 160), "0 16 160 76")]
    cases += [(CameraConfig, "crop", v, FieldTypeError) for v in ((0.0, 16, 160, 76), None)]
    cases += [(CameraConfig, "input_shape", v, ValueError) for v in ((0, 32), (61, 32))]
    cases += [(CameraConfig, "input_shape", v, FieldTypeError) for v in ((10,), (10.0, 32))]
    cases += [(WorldConfig, "camera", v, FieldTypeError) for v in (None, {}, "default")]
    return cases


BAD_CONFIG_CASES = _bad_cases()


@pytest.mark.parametrize(
    "cls,field,value,error",
    BAD_CONFIG_CASES,
    ids=[f"{c.__name__}.{f}={v!r}"[:60] for c, f, v, _ in BAD_CONFIG_CASES],
)
def test_every_bad_config_value_is_a_named_error(cls, field, value, error):
    with pytest.raises(error, match=rf"{cls.__name__}\.{field}") as info:
        cls(**{**DEFAULTS[cls], field: value})
    if error is FieldTypeError:
        assert isinstance(info.value, TypeError) and isinstance(info.value, ValueError)


BAD_EXPERIMENT_FIELDS = {
    "name": ["", "../x", "/abs", "a/b", None, 3],
    "world": [None, {}, EXPERIMENT_1.network],
    "network": [None, EXPERIMENT_1.world],
    "curriculum": [None, 0.7],
    "train_trials": [0, -1, 2.5, True, math.inf, "100", None],
    "test_trials": [-1, 1.0, False],
    "eval_every": [0, 0.5, None],
    "eval_trials": [-1, 2.0, math.nan],
    "bootstrap_on_truncation": ["abc", 1, 0, None, "True"],
}


@pytest.mark.parametrize(
    "field,value",
    [(f, v) for f, vs in BAD_EXPERIMENT_FIELDS.items() for v in vs],
)
def test_every_bad_experiment_field_is_a_named_error(field, value):
    with pytest.raises(ValueError, match=rf"ExperimentConfig\.{field}"):
        dataclasses.replace(EXPERIMENT_1, **{field: value})


def test_numpy_numbers_are_accepted_and_stored_as_plain_python():
    c = NetworkConfig(n_features=np.int32(7), beta_s=np.float32(50), eps_w=np.int64(0))
    assert type(c.n_features) is int and type(c.beta_s) is float and type(c.eps_w) is float
    w = WorldConfig(max_steps=np.uint8(20), step_forward=np.float64(0.1))
    assert type(w.max_steps) is int and type(w.step_forward) is float
    cam = CameraConfig(crop=[np.int64(0), 16, 160, 76])
    assert cam.crop == (0, 16, 160, 76) and all(type(v) is int for v in cam.crop)


# --- hypothesis: random wrong types and values always raise the named error -------------------

_wrong_type = st.one_of(
    st.none(),
    st.booleans(),
    st.text(max_size=5),
    st.lists(st.integers(), max_size=2),
    st.complex_numbers(allow_nan=False, allow_infinity=False).filter(lambda z: z.imag != 0),
)
_numeric_fields = [(cls, f) for cls, fields in RANGES.items() for f in fields]


@settings(max_examples=300, deadline=None)
@given(data=st.data())
def test_random_wrong_types_raise_the_named_type_error(data):
    cls, field = data.draw(st.sampled_from(_numeric_fields))
    value = data.draw(_wrong_type)
    with pytest.raises(FieldTypeError, match=rf"{cls.__name__}\.{field}"):
        cls(**{**DEFAULTS[cls], field: value})


@settings(max_examples=300, deadline=None)
@given(data=st.data())
def test_random_values_are_accepted_only_in_range(data):
    """Any finite value either constructs a config that holds exactly it, or raises the named
    ValueError; non-finite values always raise."""
    cls, field = data.draw(st.sampled_from(_numeric_fields))
    if field in INTEGER_FIELDS[cls]:
        value = data.draw(st.integers(-(10**6), 10**7))
    else:
        value = data.draw(st.floats(allow_nan=True, allow_infinity=True, width=64))
    try:
        config = cls(**{**DEFAULTS[cls], field: value})
    except ValueError as exc:
        # The field itself, or a cross-field constraint that names another field of the class
        # (e.g. a narrow frame no longer holds the crop).
        assert f"{cls.__name__}." in str(exc)
        return
    assert math.isfinite(value) and getattr(config, field) == value


# --- actions -------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def env():
    return DockingEnv(seed=0)


@pytest.mark.parametrize(
    "action",
    [
        True,
        False,
        np.bool_(True),
        1.0,
        1.5,
        np.float32(2),
        math.nan,
        math.inf,
        -math.inf,
        "1",
        None,
        [1],
        np.array([1]),
        np.array(1.0),
        -1,
        4,
        np.int64(4),
        10**30,
        1 + 0j,
    ],
    ids=repr,
)
def test_bad_actions_are_a_value_error(env, action):
    env.reset()
    with pytest.raises(ValueError, match="action"):
        env.step(action)


@pytest.mark.parametrize("action", [0, 3, np.int8(1), np.uint64(2), np.array(3), np.int64(0)])
def test_integer_actions_of_every_kind_are_accepted(env, action):
    env.reset()
    env.step(action)
    assert env.steps == 1


def test_a_frame_larger_than_the_offscreen_buffer_is_a_clear_error(env):
    with pytest.raises(ValueError, match="offscreen framebuffer"):
        DockingEnv(WorldConfig(camera=CameraConfig(width=1280, height=960, crop=(0, 0, 1280, 60))))
    with pytest.raises(ValueError, match="offscreen framebuffer"):
        env.render_view(width=2000, height=1500)


def _import_world_with(backend: str) -> subprocess.CompletedProcess:
    environment = {**os.environ, "MUJOCO_GL": backend}
    environment.pop("PYOPENGL_PLATFORM", None)
    return subprocess.run(
        [sys.executable, "-c", "import docking.world"],
        env=environment,
        capture_output=True,
        text=True,
        timeout=120,
    )


def test_an_unknown_backend_is_named_with_the_choices():
    done = _import_world_with("vulkan")
    assert done.returncode != 0
    assert "RenderingUnavailable" in done.stderr and "MUJOCO_GL='vulkan'" in done.stderr
    assert "egl" in done.stderr


def test_a_missing_backend_library_says_what_to_install():
    import ctypes.util

    if ctypes.util.find_library("OSMesa") is not None:
        pytest.skip("OSMesa is installed here")
    done = _import_world_with("osmesa")
    assert done.returncode != 0
    assert "RenderingUnavailable" in done.stderr and "libosmesa6" in done.stderr


# --- the network ---------------------------------------------------------------------------

_SMALL = NetworkConfig(n_inputs=12, n_features=5, n_actions=4, beta_s=20.0, eps_w=0.5)
_finite = st.floats(-1e6, 1e6, allow_nan=False, width=64)


def _network(seed: int) -> Network:
    net = Network(_SMALL, np.random.default_rng(seed))
    net.Q[:] = np.random.default_rng(seed + 1).random(net.Q.shape)
    return net


@settings(max_examples=200, deadline=None)
@given(
    seed=st.integers(0, 2**16),
    image=hnp.arrays(np.float64, 12, elements=_finite),
    a=st.integers(0, 3),
    delta=_finite,
)
def test_finite_inputs_keep_the_network_finite_with_unit_non_negative_rows(seed, image, a, delta):
    net = _network(seed)
    I = net.prepare(image)
    s = net.features(I)
    assert np.isfinite(s).all() and abs(s.sum() - 1) < 1e-12 and s.min() >= 0
    p = net.action_probabilities(s, 2.0)
    assert np.isfinite(p).all() and abs(p.sum() - 1) < 1e-12
    try:
        net.update(I, s, a, delta)
    except ValueError:  # only when Q would overflow; then nothing changed (tested below)
        pass
    assert np.isfinite(net.W).all() and np.isfinite(net.Q).all()
    assert net.W.min() >= 0
    np.testing.assert_allclose(np.linalg.norm(net.W, axis=1), 1.0, rtol=1e-12)


_bad_updates = st.sampled_from(
    [
        ("I", np.zeros(11)),
        ("I", np.full(12, np.nan)),
        ("I", np.full(12, np.inf)),
        ("I", [0.1] * 12),
        ("s", np.zeros(4)),
        ("s", np.array([np.nan, 0, 0, 0, 1.0])),
        ("s", np.array([np.inf, 0, 0, 0, 0.0])),
        ("a", True),
        ("a", 4),
        ("a", -1),
        ("a", 1.0),
        ("a", "0"),
        ("delta", math.nan),
        ("delta", math.inf),
        ("delta", True),
    ]
)


@settings(max_examples=100, deadline=None)
@given(seed=st.integers(0, 2**16), bad=_bad_updates)
def test_a_rejected_update_changes_nothing(seed, bad):
    net = _network(seed)
    I = net.prepare(np.random.default_rng(seed).random(12))
    args = {"I": I, "s": net.features(I), "a": 1, "delta": 0.5}
    name, value = bad
    args[name] = value
    W, Q = net.W.copy(), net.Q.copy()
    with pytest.raises(ValueError):
        net.update(**args)
    np.testing.assert_array_equal(net.W, W)
    np.testing.assert_array_equal(net.Q, Q)


def test_an_update_that_would_overflow_q_changes_nothing():
    net = Network.from_weights(
        dataclasses.replace(_SMALL, eps_q=100.0), _network(0).W, _network(0).Q
    )
    I = net.prepare(np.ones(12))
    W, Q = net.W.copy(), net.Q.copy()
    with pytest.raises(ValueError, match="non-finite"):
        net.update(I, net.features(I), 2, 1e308)
    np.testing.assert_array_equal(net.W, W)
    np.testing.assert_array_equal(net.Q, Q)


def test_run_trial_refuses_bad_options(env):
    net = Network(NetworkConfig(), np.random.default_rng(0))
    rng = np.random.default_rng(0)
    for kwargs, field in (
        ({"learn": 1}, "learn"),
        ({"learn": True, "bootstrap_on_truncation": "abc"}, "bootstrap_on_truncation"),
        ({"learn": False, "beta_a": -1.0}, "beta_a"),
        ({"learn": False, "beta_a": math.inf}, "beta_a"),
    ):
        with pytest.raises(ValueError, match=field):
            run_trial(env, net, rng, **kwargs)
    with pytest.raises(ValueError, match="rng"):
        run_trial(env, net, 0, learn=False)
    with pytest.raises(ValueError, match="env"):
        run_trial(object(), net, rng, learn=False)


def test_experiment_config_checks_cross_field_consistency():
    with pytest.raises(ValueError, match="n_inputs"):
        dataclasses.replace(EXPERIMENT_1, network=NetworkConfig(n_inputs=100))
    assert isinstance(EXPERIMENT_1, ExperimentConfig)
