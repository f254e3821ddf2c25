"""Tests of docking.network: Eq. (1)-(8) and (12)-(16) of Kleesiek et al. (2011)."""

import dataclasses
import os

import numpy as np
import pytest

from docking.network import Network, NetworkConfig, finite_difference_gradient

SMALL = dict(n_inputs=12, n_features=3, n_actions=2)


def random_net(seed, q_scale=1.0, **overrides):
    """A small network with random non-negative W (unit rows) and random signed Q."""
    cfg = NetworkConfig(**{**SMALL, **overrides})
    rng = np.random.default_rng(seed)
    net = Network(cfg, rng)
    net.Q[:] = q_scale * rng.normal(size=net.Q.shape)
    return net, rng


# ---------------------------------------------------------------- configuration


@pytest.mark.parametrize(
    "field, value",
    [
        ("n_inputs", 0),
        ("n_inputs", 3.5),
        ("n_features", -1),
        ("n_actions", 0),
        ("n_actions", True),
        ("beta_s", 0.0),
        ("beta_s", -1.0),
        ("beta_s", float("inf")),
        ("beta_a_train", 0.0),
        ("beta_a_test", -2.0),
        ("gamma", -0.1),
        ("gamma", 1.5),
        ("eps_q", -0.1),
        ("eps_w", float("nan")),
        ("q_init", -1.0),
        ("rule", "hebbian"),
        ("normalize_input", "yes"),
    ],
)
def test_config_validation_names_parameter(field, value):
    with pytest.raises(ValueError, match=field):
        NetworkConfig(**{field: value})


def test_config_defaults_are_the_papers():
    cfg = NetworkConfig()
    assert (cfg.n_inputs, cfg.n_actions) == (320, 4)
    assert cfg.beta_s == 100.0  # Eq. (2)
    assert (cfg.beta_a_train, cfg.beta_a_test) == (2.0, 100.0)  # Eq. (4)
    assert cfg.gamma == 0.9  # Eq. (6)
    assert cfg.rule == "nonlocal"
    with pytest.raises(dataclasses.FrozenInstanceError):
        cfg.gamma = 0.5


def test_init_weights():
    cfg = NetworkConfig(q_init=0.3)
    net = Network(cfg, np.random.default_rng(0))
    assert net.W.shape == (4, 320) and net.Q.shape == (4, 4)
    assert (net.W >= 0).all()
    np.testing.assert_allclose(np.linalg.norm(net.W, axis=1), 1.0, rtol=1e-12)
    assert (net.Q >= 0).all() and (net.Q <= 0.3).all() and net.Q.std() > 0
    assert (Network(NetworkConfig(), np.random.default_rng(0)).Q == 0).all()
    with pytest.raises(ValueError, match="rng"):
        Network(cfg, 0)


def test_same_seed_same_weights_and_q_init_changes_nothing_else():
    rngs = [np.random.default_rng(7) for _ in range(3)]
    a = Network(NetworkConfig(), rngs[0])
    b = Network(NetworkConfig(), rngs[1])
    c = Network(NetworkConfig(q_init=0.1), rngs[2])
    assert a.W.tobytes() == b.W.tobytes() == c.W.tobytes()
    assert len({r.random() for r in rngs}) == 1  # generators advanced identically


# ---------------------------------------------------------------- forward pass


@pytest.mark.filterwarnings("ignore:overflow encountered:RuntimeWarning")
def test_prepare_shapes_and_normalization():
    net = Network(NetworkConfig(), np.random.default_rng(0))
    obs = np.random.default_rng(1).random((10, 32), dtype=np.float32)
    I = net.prepare(obs)
    assert I.shape == (320,) and I.dtype == np.float64
    assert np.linalg.norm(I) == pytest.approx(1.0, rel=1e-12)
    np.testing.assert_allclose(I * np.linalg.norm(obs.astype(np.float64)), obs.ravel(), rtol=1e-6)
    assert (net.prepare(np.zeros((10, 32))) == 0).all()  # zero input stays zero
    x = np.ones(320)
    I = net.prepare(x)
    assert not np.shares_memory(I, x)
    raw = Network(NetworkConfig(normalize_input=False), np.random.default_rng(0))
    np.testing.assert_array_equal(raw.prepare(obs), obs.ravel().astype(np.float64))
    with pytest.raises(ValueError, match="320"):
        net.prepare(np.zeros((10, 31)))
    with pytest.raises(ValueError, match="NaN"):
        net.prepare(np.full(320, np.nan))
    big = net.prepare(np.full(320, 1e200))  # squares overflow, still unit length
    assert np.linalg.norm(big) == pytest.approx(1.0)


def test_features_and_probabilities_are_softmaxes():
    net, _ = random_net(0, beta_s=3.0)
    I = net.prepare(np.arange(12.0))
    s = net.features(I)
    h = net.W @ I  # Eq. (1)
    expected = np.exp(3.0 * h) / np.exp(3.0 * h).sum()  # Eq. (2)
    np.testing.assert_allclose(s, expected, rtol=1e-12)
    p = net.action_probabilities(s, 2.0)
    hq = net.Q @ s  # Eq. (3)
    np.testing.assert_allclose(p, np.exp(2 * hq) / np.exp(2 * hq).sum(), rtol=1e-12)  # Eq. (4)
    assert net.value(I, 1) == pytest.approx(net.Q[1] @ s, rel=1e-14)  # Eq. (5)
    with pytest.raises(ValueError, match="action"):
        net.value(I, -1)
    with pytest.raises(ValueError, match="beta_a"):
        net.action_probabilities(s, -1.0)


@pytest.mark.parametrize("normalize", [True, False])
def test_extreme_inputs_give_finite_outputs(normalize):
    cfg = NetworkConfig(normalize_input=normalize, beta_s=1e6)
    net = Network(cfg, np.random.default_rng(0))
    net.Q[:] = np.random.default_rng(1).normal(size=net.Q.shape)
    zero = net.prepare(np.zeros((10, 32)))
    s = net.features(zero)
    np.testing.assert_allclose(s, 0.25)  # all-zero input: uniform state
    for obs in (
        np.full((10, 32), 1e6),
        np.random.default_rng(2).random(320) * 1e6,
        np.eye(32)[:10],
    ):
        I = net.prepare(obs)
        s = net.features(I)
        assert np.isfinite(s).all() and s.sum() == pytest.approx(1.0)
        for beta_a in (0.0, 2.0, 1e8):
            p = net.action_probabilities(s, beta_a)
            assert np.isfinite(p).all() and p.sum() == pytest.approx(1.0)
        assert all(np.isfinite(net.value(I, a)) for a in range(4))
        dQ, dW = net.value_gradient(I, 0)
        assert np.isfinite(dQ).all() and np.isfinite(dW).all()


@pytest.mark.filterwarnings("ignore:overflow encountered:RuntimeWarning")
def test_softmax_overflow_limit():
    net = Network(NetworkConfig(normalize_input=False, beta_s=1e6), np.random.default_rng(0))
    s = net.features(net.prepare(np.full(320, 1e300)))  # beta_s * h overflows to inf
    assert np.isfinite(s).all() and s.sum() == pytest.approx(1.0)


def test_select_action_follows_eq4_and_is_reproducible():
    net, _ = random_net(3, q_scale=0.5, n_actions=4)
    s = net.features(net.prepare(np.linspace(0, 1, 12)))
    p = net.action_probabilities(s, 2.0)
    draws = [net.select_action(s, np.random.default_rng(11), 2.0) for _ in range(3)]
    assert len(set(draws)) == 1
    rng = np.random.default_rng(5)
    counts = np.bincount([net.select_action(s, rng, 2.0) for _ in range(20000)], minlength=4)
    np.testing.assert_allclose(counts / 20000, p, atol=0.015)
    # beta_a large: greedy
    greedy = {net.select_action(s, rng, 1e6) for _ in range(50)}
    assert greedy == {int(np.argmax(net.Q @ s))}


# ---------------------------------------------------------------- gradient (Eq. 12-16)


@pytest.mark.parametrize("seed", range(5))
@pytest.mark.parametrize("beta_s", [2.0, 5.0])
def test_value_gradient_matches_finite_differences(seed, beta_s):
    net, rng = random_net(seed, beta_s=beta_s, normalize_input=False)
    I = rng.random(net.config.n_inputs)
    a = int(rng.integers(net.config.n_actions))
    s = net.features(I)
    assert s.max() < 0.95  # softmax not saturated: a meaningful check
    dQ, dW = net.value_gradient(I, a)
    W_before, Q_before = net.W.copy(), net.Q.copy()
    numeric_Q, numeric_W = finite_difference_gradient(net, I, a, h=1e-6)
    np.testing.assert_array_equal(net.W, W_before)  # restored exactly
    np.testing.assert_array_equal(net.Q, Q_before)
    for name, numeric, analytic in (("Q", numeric_Q, dQ), ("W", numeric_W, dW)):
        rel = np.linalg.norm(numeric - analytic) / np.linalg.norm(analytic)
        assert rel < 1e-5, (name, rel)


def test_value_gradient_formula():
    net, rng = random_net(1, beta_s=4.0)
    I = net.prepare(rng.random(12))
    dQ, dW = net.value_gradient(I, 1)
    s = net.features(I)
    assert (dQ[0] == 0).all()
    np.testing.assert_allclose(dQ[1], s)  # Eq. (12)
    bracket = net.Q[1] - net.Q[1] @ s
    np.testing.assert_allclose(dW, 4.0 * np.outer(s * bracket, I))  # Eq. (16) times beta_s


# ---------------------------------------------------------------- learning rule (Eq. 7-8)


def _rectify_normalize(W):
    W = np.maximum(W, 0.0)
    return W / np.linalg.norm(W, axis=1, keepdims=True)


@pytest.mark.parametrize("rule", ["nonlocal", "local"])
def test_update_is_eq7_and_eq8(rule):
    net, rng = random_net(2, rule=rule, eps_q=0.3, eps_w=0.01, beta_s=4.0)
    I = net.prepare(rng.random(12))
    s = net.features(I)
    a, delta = 1, 0.7
    W0, Q0 = net.W.copy(), net.Q.copy()
    _, dW = net.value_gradient(I, a)  # uses the pre-update Q
    inc_Q, inc_W = net.increments(I, s, a, delta)
    net.update(I, s, a, delta)
    expected_Q = Q0.copy()
    expected_Q[a] += 0.3 * delta * s  # Eq. (7)
    np.testing.assert_allclose(net.Q, expected_Q, rtol=1e-14)
    if rule == "nonlocal":
        step = 0.01 * delta * dW / 4.0  # Eq. (8) = exact gradient without beta_s
    else:
        step = 0.01 * delta * np.outer(s, I)  # local rule: no bracket
    np.testing.assert_allclose(inc_Q, expected_Q - Q0, rtol=1e-14, atol=1e-16)
    np.testing.assert_allclose(inc_W, step, rtol=1e-12, atol=1e-16)
    np.testing.assert_allclose(net.W, _rectify_normalize(W0 + step), rtol=1e-12, atol=1e-15)


@pytest.mark.filterwarnings("ignore:overflow encountered:RuntimeWarning")
@pytest.mark.parametrize("rule", ["nonlocal", "local"])
def test_update_keeps_W_nonnegative_unit_rows(rule):
    net, rng = random_net(4, rule=rule, n_inputs=30, n_features=5, n_actions=3)
    deltas = [-1e6, -50.0, -1.0, -0.3, 0.0, 0.3, 1.0, 50.0, 1e6, 1e300, -1e300]
    deltas += list(rng.normal(scale=10.0, size=200))
    for delta in deltas:
        I = net.prepare(rng.random(30) * rng.integers(0, 2, 30))  # sparse non-negative inputs
        s = net.features(I)
        net.update(I, s, int(rng.integers(3)), float(delta))
        assert np.isfinite(net.W).all()
        assert (net.W >= 0).all()
        np.testing.assert_allclose(np.linalg.norm(net.W, axis=1), 1.0, rtol=1e-12)
    with pytest.raises(ValueError, match="delta"):
        net.update(I, s, 0, float("nan"))
    with pytest.raises(ValueError, match="action"):
        net.update(I, s, 3, 0.1)


def test_dead_row_keeps_previous_value():
    cfg = NetworkConfig(n_inputs=4, n_features=2, n_actions=1, rule="local", eps_w=1.0)
    W = np.array([[0.6, 0.8, 0.0, 0.0], [0.0, 0.0, 0.6, 0.8]])
    net = Network.from_weights(cfg, W, np.zeros((1, 2)))
    I = net.prepare([3.0, 4.0, 0.0, 0.0])  # = row 0
    s = net.features(I)
    net.update(I, s, 0, -10.0)  # pushes every weight of row 0 below zero
    np.testing.assert_array_equal(net.W[0], W[0])  # row 0 would be all-zero: kept
    np.testing.assert_array_equal(net.W[1], W[1])  # row 1 not touched by this input


def test_nonlocal_update_vanishes_at_clear_winner():
    cfg = NetworkConfig(n_inputs=4, n_features=2, n_actions=2, eps_w=1.0, eps_q=0.0)
    W = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]])
    net = Network.from_weights(cfg, W, [[1.0, 0.2], [0.3, 0.5]])
    I = net.prepare([1.0, 0.0, 0.5, 0.0])
    s = np.array([1.0, 0.0])  # exactly one winner (Sec. II-B)
    net.update(I, s, 0, 0.8)
    np.testing.assert_array_equal(net.W, W)
    local = Network.from_weights(dataclasses.replace(cfg, rule="local"), W, net.Q)
    local.update(I, s, 0, 0.8)
    assert not np.array_equal(local.W, W)  # the local rule still moves the winner


# ---------------------------------------------------------------- persistence


def test_save_load_roundtrip(tmp_path):
    net, _ = random_net(5, rule="local", gamma=0.8, normalize_input=False)
    path = tmp_path / "net.npz"
    net.save(path)
    net.save(path)  # overwrite is fine
    back = Network.load(path)
    assert back.config == net.config
    assert back.W.tobytes() == net.W.tobytes() and back.Q.tobytes() == net.Q.tobytes()
    assert os.listdir(tmp_path) == ["net.npz"]  # no temporary file left behind
    other = net.copy()
    other.W[0, 0] += 1.0
    other.Q[0, 0] += 1.0
    assert other.W[0, 0] != net.W[0, 0] and other.Q[0, 0] != net.Q[0, 0]


def test_from_weights_checks_shapes():
    cfg = NetworkConfig(**SMALL)
    with pytest.raises(ValueError, match="W must have shape"):
        Network.from_weights(cfg, np.zeros((2, 12)), np.zeros((2, 3)))
    with pytest.raises(ValueError, match="Q must have shape"):
        Network.from_weights(cfg, np.zeros((3, 12)), np.zeros((3, 3)))


# ---------------------------------------------------------------- synthetic task

# Weber & Triesch (2009), "Goal-directed feature learning": with the delta-modulated feature
# rule, the feature layer learns the input components that decide the rewarded action and
# neglects the rest.  One-step task: every pixel is uniform noise in [0, 0.5], except that the
# block of 2 pixels belonging to the class (4 classes) is set to 1.  Reward 1 for the action
# equal to the class.
N_CLASSES, BLOCK, N_PIX, NOISE = 4, 2, 64, 0.5
N_INFO = N_CLASSES * BLOCK  # informative pixels: chance fraction 8/64 = 0.125


def _sample(rng):
    c = int(rng.integers(N_CLASSES))
    x = NOISE * rng.random(N_PIX)
    x[c * BLOCK : (c + 1) * BLOCK] = 1.0
    return x, c


def _informative_fraction(W):
    """Fraction of the squared row length (= 1 per row) on the informative pixels."""
    return float((W[:, :N_INFO] ** 2).sum() / (W**2).sum())


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_synthetic_task_learns_policy_and_relevant_features(seed):
    # beta_s = 5 (not the paper's 100): the non-local rule vanishes at a clear winner
    # (Sec. II-B), and at beta_s = 100 the winner is clear as soon as the features separate
    # the classes by a tiny margin, so feature learning stops early there (the policy is
    # still learned; the informative fraction then only reaches about 0.2).
    cfg = NetworkConfig(
        n_inputs=N_PIX,
        n_features=4,
        n_actions=N_CLASSES,
        beta_s=5.0,
        eps_q=0.5,
        eps_w=1.0,
        rule="nonlocal",
    )
    rng = np.random.default_rng(seed)
    net = Network(cfg, rng)
    before = _informative_fraction(net.W)
    for _ in range(1500):
        x, c = _sample(rng)
        I = net.prepare(x)
        s = net.features(I)
        a = net.select_action(s, rng, cfg.beta_a_train)
        r = 1.0 if a == c else 0.0
        net.update(I, s, a, r - float(net.Q[a] @ s))  # one-step episode: v' = 0, Eq. (6)

    test_rng = np.random.default_rng(100 + seed)
    samples = [_sample(test_rng) for _ in range(400)]
    greedy = [int(np.argmax(net.Q @ net.features(net.prepare(x)))) for x, _ in samples]
    accuracy = np.mean([g == c for g, (_, c) in zip(greedy, samples, strict=False)])
    assert accuracy >= 0.98

    # Baseline: the class-mean inputs (what unsupervised averaging would converge to).
    means = np.array(
        [np.mean([net.prepare(x) for x, c in samples if c == k], axis=0) for k in range(4)]
    )
    means /= np.linalg.norm(means, axis=1, keepdims=True)
    after = _informative_fraction(net.W)
    assert before < 0.2  # random start: about the chance fraction 0.125
    assert after > 0.7
    assert after > 1.8 * _informative_fraction(means)  # noise pixels actively suppressed


def test_a_constant_feature_delta_replaces_delta_in_eq_8_only():
    import dataclasses as dc

    base = NetworkConfig(n_inputs=6, n_features=3, n_actions=2, eps_w=0.3)
    rng = np.random.default_rng(0)
    net = Network(base, rng)
    net.Q[:] = rng.random(net.Q.shape)
    control = Network.from_weights(dc.replace(base, feature_delta=0.25), net.W, net.Q)
    I = net.prepare(rng.random(6))
    s = net.features(I)
    dQ, dW = net.increments(I, s, 1, 0.25)
    dQc, dWc = control.increments(I, s, 1, -0.8)  # any delta: W moves as if delta = 0.25
    np.testing.assert_array_equal(dWc, dW)
    np.testing.assert_allclose(dQc, dQ * (-0.8 / 0.25))  # Eq. (7) still uses delta
    control.update(I, s, 1, -0.8)
    net.update(I, s, 1, 0.25)
    np.testing.assert_array_equal(control.W, net.W)
    with pytest.raises(ValueError, match="feature_delta"):
        NetworkConfig(feature_delta=float("nan"))


def test_without_a_feature_layer_the_network_is_linear_sarsa_on_the_pixels():
    config = NetworkConfig(n_inputs=6, n_features=6, n_actions=3, feature_layer="none")
    net = Network(config, np.random.default_rng(1))
    np.testing.assert_array_equal(net.W, np.eye(6))
    I = net.prepare(np.arange(6.0))
    assert net.features(I) is I
    W = net.W.copy()
    net.update(I, I, 2, 0.5)
    np.testing.assert_allclose(net.Q[2], config.eps_q * 0.5 * I)
    np.testing.assert_array_equal(net.W, W)
    assert net.value(I, 2) == pytest.approx(config.eps_q * 0.5 * I @ I)
    dQ, dW = net.value_gradient(I, 2)
    np.testing.assert_array_equal(dQ[2], I) and np.testing.assert_array_equal(dW, 0 * W)
    with pytest.raises(ValueError, match="n_features must equal n_inputs"):
        NetworkConfig(n_features=4, feature_layer="none")
    with pytest.raises(ValueError, match="feature_layer"):
        NetworkConfig(feature_layer="relu")


# -- the controls of the study's second edition: the permuted delta, the SOM ----------------


def _step_inputs(net, rng):
    I = net.prepare(rng.random((10, 32)).astype(np.float32))
    return I, net.features(I)


def test_the_permutation_control_modulates_eq8_by_the_given_delta_and_eq7_by_delta():
    rng = np.random.default_rng(0)
    cfg = NetworkConfig(n_features=4, permute_delta=True)
    net = Network(cfg, np.random.default_rng(1))
    I, s = _step_inputs(net, rng)
    dQ, dW = net.increments(I, s, 2, 0.5, feature_delta=-0.25)
    plain = Network(NetworkConfig(n_features=4), np.random.default_rng(1))
    dQ0, dW0 = plain.increments(I, s, 2, 0.5)
    np.testing.assert_array_equal(dQ, dQ0)  # Eq. (7): this step's delta
    np.testing.assert_allclose(dW, -0.5 * dW0)  # Eq. (8): the permuted delta, -0.25 / 0.5
    before = net.W.copy()
    net.update(I, s, 2, 0.5, -0.25)
    assert not np.array_equal(before, net.W)


def test_the_permuted_delta_is_required_exactly_in_the_permutation_control():
    rng = np.random.default_rng(0)
    permuting = Network(NetworkConfig(n_features=4, permute_delta=True), np.random.default_rng(1))
    I, s = _step_inputs(permuting, rng)
    with pytest.raises(ValueError, match="permuted feature_delta is required"):
        permuting.update(I, s, 0, 0.5)
    plain = Network(NetworkConfig(n_features=4), np.random.default_rng(1))
    with pytest.raises(ValueError, match="permuted feature_delta is required"):
        plain.update(I, s, 0, 0.5, 0.1)
    with pytest.raises(ValueError, match="exclude each other"):
        NetworkConfig(permute_delta=True, feature_delta=0.1)


@pytest.mark.parametrize(("n", "grid"), [(36, (6, 6)), (4, (2, 2)), (12, (3, 4)), (7, (1, 7))])
def test_the_som_grid_is_the_most_nearly_square_factorisation(n, grid):
    assert Network.som_grid(n) == grid


def test_a_som_step_is_kohonens_rule_and_with_a_narrow_neighbourhood_the_competitive_one():
    rng = np.random.default_rng(3)
    net = Network(NetworkConfig(n_features=36), np.random.default_rng(4))
    I = net.prepare(rng.random((10, 32)).astype(np.float32))
    before = net.W.copy()
    j = net.som_update(I, 0.5, sigma=1.5)
    assert j == int(np.argmax(before @ I))
    grid = np.array([(k // 6, k % 6) for k in range(36)])
    g = np.exp(-np.sum((grid - grid[j]) ** 2, axis=1) / (2 * 1.5**2))
    expected = np.maximum(before + 0.5 * g[:, None] * (I - before), 0)
    expected /= np.linalg.norm(expected, axis=1, keepdims=True)
    np.testing.assert_allclose(net.W, expected, rtol=0, atol=1e-12)
    assert (net.W >= 0).all()

    narrow = Network(NetworkConfig(n_features=36), np.random.default_rng(4))
    competitive = Network(NetworkConfig(n_features=36), np.random.default_rng(4))
    assert narrow.som_update(I, 0.3, sigma=0.01) == competitive.competitive_update(I, 0.3) == j
    np.testing.assert_allclose(narrow.W, competitive.W, rtol=0, atol=1e-12)
    zero = narrow.W.copy()
    assert narrow.som_update(np.zeros(320), 0.5, 1.0) == -1
    np.testing.assert_array_equal(zero, narrow.W)
