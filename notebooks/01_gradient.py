# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: percent
#       format_version: '1.3'
#       jupytext_version: 1.19.6
#   kernelspec:
#     display_name: Python 3 (ipykernel)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 01 — The feature learning rule (Eq. 8) is gradient descent on Eq. (9)
#
# Kleesiek et al. (2011), Sec. II-B, derive the rule that trains the visual features $W$ from
# the same prediction error $\delta$ that trains the action weights $Q$.  This notebook
# re-derives Eq. (9)–(16) step by step and checks the result three ways, each with an `assert`:
#
# 1. **symbolically** (SymPy) on a small network: the softmax identities Eq. (14)–(15) and the
#    gradient Eq. (16);
# 2. **numerically**: finite differences against `docking.network.Network.value_gradient`, at a
#    small $\beta^s$ and at the paper's $\beta^s = 100$;
# 3. **local vs non-local**: what the local rule (Eq. 8 without the bracket) keeps and loses.
#
# All network code lives in `docking/network.py`; this notebook only calls it.

# %%
import dataclasses
import inspect

import matplotlib.pyplot as plt
import numpy as np
import sympy as sp
from IPython.display import Code, display

from docking.network import Network, NetworkConfig


def show_code(function):
    """Display the library's source of ``function`` (what runs, not a copy of it)."""
    display(Code(inspect.getsource(function), language="python"))


# %% [markdown]
# ## The network (Sec. II-A)
#
# Input pixels $I$, feature layer $s$, action layer $a$:
#
# $$h_j = \sum_n W_{jn} I_n \quad (1) \qquad s_j = \frac{e^{\beta^s h_j}}{\sum_k e^{\beta^s h_k}} \quad (2)$$
#
# The library computes Eq. (1)-(2) in `Network.features` (`_softmax` subtracts the maximum
# before exponentiating, so that $\beta^s = 100$ cannot overflow):

# %%
show_code(Network.features)

# %% [markdown]
# $$h_i = \sum_j Q_{ij} s_j \quad (3) \qquad \mathrm{Prob}(a_i = 1) = \frac{e^{\beta^a h_i}}{\sum_k e^{\beta^a h_k}} \quad (4)$$
#
# The value of the chosen action ($a$ is one-hot, $a_i = 1$) and the SARSA prediction error:
#
# $$v = \sum_{k,l} Q_{kl} a_k s_l = \sum_l Q_{il} s_l \quad (5) \qquad \delta = r + \gamma v' - v \quad (6)$$
#
# The learning rules:
#
# $$\Delta Q_{ij} \propto \delta a_i s_j \quad (7) \qquad \Delta W_{jn} \propto \delta s_j I_n \Big(Q_{ij} - \sum_k Q_{ik} s_k\Big) \quad (8)$$
#
# The library's Eq. (7)-(8), in `Network.update`, with the learning rates $\varepsilon_Q$,
# $\varepsilon_W$ for "$\propto$"; `_feature_factor` is $s_j$ times the bracket of Eq. (8)
# for the non-local rule (and $s_j$ alone for the local rule of Sec. II-B):

# %%
show_code(Network.update)
show_code(Network._feature_factor)

# %% [markdown]
# ## Derivation (Sec. II-B)
#
# **Energy.** With parameters $\theta = (Q, W)$, the values $v(\theta)$ should approach the true
# values $V^\pi$ under the on-policy distribution $P^\pi$ of state–action pairs:
#
# $$E(\theta) = \frac12 \sum_{s,a} P^\pi(s,a) \big(V^\pi(s,a) - v(s,a)\big)^2 . \quad (9)$$
#
# **Target.** $V^\pi$ is unknown; SARSA replaces it by the one-step estimate, so the error is
#
# $$V^\pi - v \approx r + \gamma v' - v = \delta . \quad (10)$$
#
# **On-line gradient step.** Sampling $(s, a)$ from $P^\pi$ by acting replaces the sum, and the
# target $r + \gamma v'$ is held fixed (it is not differentiated — the "semi-gradient" of Sutton
# & Barto; $P^\pi$ is likewise treated as fixed):
#
# $$\Delta\theta \propto -\frac{\partial E}{\partial \theta} = (V^\pi - v)\frac{\partial v}{\partial \theta} = \delta \frac{\partial v}{\partial \theta} . \quad (11)$$
#
# **Action weights.** From Eq. (5), $\partial v / \partial Q_{ij} = a_i s_j$, so
#
# $$\Delta Q_{ij} \propto -\frac{\partial E}{\partial Q_{ij}} = \delta a_i s_j , \quad (12)$$
#
# which is Eq. (7).
#
# **Feature weights.** $W_{jn}$ enters only $h_j$ (Eq. 1, $\partial h_j / \partial W_{jn} = I_n$),
# but $h_j$ enters *every* $s_k$ through the softmax denominator (Eq. 2).  With $a_i = 1$:
#
# $$\Delta W_{jn} \propto -\frac{\partial E}{\partial W_{jn}} = \delta \sum_k \frac{\partial v}{\partial s_k}\frac{\partial s_k}{\partial h_j}\frac{\partial h_j}{\partial W_{jn}} = \delta \sum_k Q_{ik} \frac{\partial s_k}{\partial h_j} I_n . \quad (13)$$
#
# **Softmax identities.** Differentiating Eq. (2):
#
# $$\frac{\partial s_j}{\partial h_j} = \beta^s s_j (1 - s_j) \quad (14) \qquad \frac{\partial s_k}{\partial h_j} = -\beta^s s_k s_j \quad (k \neq j) \quad (15)$$
#
# The paper writes (14)–(15) without the factor $\beta^s$; it only rescales the step.
#
# **Result.** Splitting the sum of Eq. (13) into $k = j$ and $k \neq j$:
#
# $$\begin{aligned}
# \frac{\partial v}{\partial W_{jn}}
#   &= \beta^s \Big[ Q_{ij} s_j (1 - s_j) - \sum_{k \neq j} Q_{ik} s_k s_j \Big] I_n \\
#   &= \beta^s \Big[ Q_{ij} s_j - \sum_{k} Q_{ik} s_k s_j \Big] I_n \\
#   &= \beta^s\, s_j I_n \Big(Q_{ij} - \sum_k Q_{ik} s_k\Big) ,
# \end{aligned} \quad (16)$$
#
# so $\Delta W_{jn} \propto \delta\, \partial v / \partial W_{jn}$ is Eq. (8).
#
# ## What the code does with this
#
# * **Sign convention.** $\delta$ = target − estimate (Eq. 6).  Every update *adds*
#   $\varepsilon\,\delta\,\partial v/\partial\theta$: a positive $\delta$ raises $v$ towards the
#   target, which is descent on $E$ (Eq. 11).
# * **$\beta^s$.** `Network.value_gradient` returns the *exact* derivative, including the factor
#   $\beta^s$ of Eq. (14)–(16).  `Network.update` (shown above) implements Eq. (7)–(8) as
#   printed, without $\beta^s$.  So the step on $W$ is a gradient step of size $\varepsilon_W / \beta^s$: with $\beta^s = 100$
#   and $\varepsilon_W = 0.05$ that is $5 \cdot 10^{-4}$ times $\delta\,\partial v/\partial W$.
#   The bracket uses $Q$ *before* its own update in the same step.
# * **Rectify and normalize** (Sec. II-A): after each step, $W \leftarrow \max(W, 0)$ and every row
#   is scaled to unit length.  For a row $w$ with a positive entry this is exactly the Euclidean
#   projection onto the non-negative part of the unit sphere: for $u \ge 0$, $|u| = 1$,
#   $|w - u|^2 = |w|^2 + 1 - 2\langle w, u\rangle$ and
#   $\langle w, u\rangle \le \langle w_+, u\rangle \le |w_+|$, with equality at
#   $u = w_+/|w_+|$.  The learning rule is therefore projected (semi-)gradient descent.

# %% [markdown]
# ## Check 1 — symbolic (SymPy)
#
# A small network: 3 feature units, 2 inputs, 2 actions, symbolic $\beta^s > 0$.  First the
# softmax identities Eq. (14)–(15) on free activations $h$, then Eq. (12) and Eq. (16) on the
# full composition $v(Q, W) = \sum_{kl} Q_{kl} a_k\, s_l(W I)$.

# %% tags=["hide-input"]
J, N, A = 3, 2, 2  # feature units, inputs, actions
beta = sp.Symbol("beta_s", positive=True)
W_sym = sp.Matrix(J, N, lambda j, n: sp.Symbol(f"W_{j}{n}", real=True))
I_sym = sp.Matrix(N, 1, lambda n, _: sp.Symbol(f"I_{n}", real=True))
Q_sym = sp.Matrix(A, J, lambda i, j: sp.Symbol(f"Q_{i}{j}", real=True))
a_sym = sp.Matrix(A, 1, lambda i, _: sp.Symbol(f"a_{i}", real=True))


def softmax_sym(h):
    """Eq. (2) on a list of symbolic activations."""
    Z = sum(sp.exp(beta * x) for x in h)
    return [sp.exp(beta * x) / Z for x in h]


# Eq. (14)-(15) on free activations h_0..h_2
h_free = sp.symbols(f"h0:{J}", real=True)
s_free = softmax_sym(h_free)
for j in range(J):
    for k in range(J):
        identity = beta * s_free[j] * (1 - s_free[j]) if j == k else -beta * s_free[j] * s_free[k]
        assert sp.simplify(sp.diff(s_free[j], h_free[k]) - identity) == 0
print("Eq. (14) and (15) hold (with the factor beta_s).")

# %% tags=["hide-input"]
h_sym = W_sym * I_sym  # Eq. (1)
s_sym = softmax_sym(list(h_sym))  # Eq. (2)
v_sym = sum(Q_sym[k, l] * a_sym[k] * s_sym[l] for k in range(A) for l in range(J))  # Eq. (5)

for i in range(A):  # Eq. (12), general a
    for j in range(J):
        assert sp.simplify(sp.diff(v_sym, Q_sym[i, j]) - a_sym[i] * s_sym[j]) == 0

for i in range(A):  # Eq. (16), for each possible chosen action i (a one-hot)
    v_i = v_sym.subs({a_sym[k]: int(k == i) for k in range(A)})
    for j in range(J):
        for n in range(N):
            bracket = Q_sym[i, j] - sum(Q_sym[i, k] * s_sym[k] for k in range(J))
            eq16 = beta * s_sym[j] * I_sym[n] * bracket
            assert sp.simplify(sp.diff(v_i, W_sym[j, n]) - eq16) == 0
print("Eq. (12) and Eq. (16) hold: dv/dW_jn = beta_s s_j I_n (Q_ij - sum_k Q_ik s_k).")

# %% [markdown]
# ## Check 2 — finite differences on `docking.network`
#
# Central differences $\big(v(\theta + h e) - v(\theta - h e)\big) / 2h$ for every entry of $Q$
# and $W$, compared with `Network.value_gradient`, on the full-size network (320 inputs,
# 4 features).  The relative error is $\|g_\text{num} - g\| / \|g\|$.

# %% tags=["hide-input"]
from docking.network import finite_difference_gradient  # noqa: E402


def relative_errors(net, I, a):
    numeric = finite_difference_gradient(net, I, a)
    exact = net.value_gradient(I, a)
    return [np.linalg.norm(n - e) / np.linalg.norm(e) for n, e in zip(numeric, exact, strict=False)]


rng = np.random.default_rng(0)
image = rng.random((10, 32)) * (rng.random((10, 32)) < 0.3)  # a sparse non-negative image

# Small beta_s: the softmax is far from saturated at any input.
net = Network(NetworkConfig(beta_s=3.0), rng)
net.Q[:] = rng.random(net.Q.shape)
I = net.prepare(image)
print("beta_s = 3:   s =", net.features(I).round(3))
for a in range(4):
    err_Q, err_W = relative_errors(net, I, a)
    print(f"  action {a}: relative error dQ {err_Q:.1e}, dW {err_W:.1e}")
    assert err_Q < 1e-5 and err_W < 1e-5

# %% [markdown]
# At $\beta^s = 100$ a random input almost always has a clear winner ($s$ nearly one-hot), where
# the $W$-gradient is nearly zero (Check 3) and a relative error is meaningless.  So we pick an
# input on the boundary between two units: $I \propto W_0 + W_1$ gives $h_0 = h_1$ exactly
# (rows of $W$ have unit length), so $s_0 = s_1$ and the softmax is not saturated there.
# The step $h = 10^{-6}$ is still small compared with the curvature scale $1/\beta^s$.

# %%
net = Network(NetworkConfig(beta_s=100.0), rng)  # the paper's beta_s, Eq. (2)
net.Q[:] = rng.random(net.Q.shape)
s_random = net.features(net.prepare(image))
print("beta_s = 100, random image:  s =", s_random.round(4))
I = net.prepare(net.W[0] + net.W[1])
s = net.features(I)
print("beta_s = 100, boundary input: s =", s.round(4))
assert s.max() < 0.9
for a in range(4):
    err_Q, err_W = relative_errors(net, I, a)
    print(f"  action {a}: relative error dQ {err_Q:.1e}, dW {err_W:.1e}")
    assert err_Q < 1e-5 and err_W < 1e-5

# %% [markdown]
# **The update is this gradient, scaled, and it descends.**  `Network.increments` returns the
# raw changes of Eq. (7)–(8) (before rectification).  For the non-local rule they are
# $\varepsilon_Q \delta\, \partial v/\partial Q$ and $(\varepsilon_W/\beta^s)\, \delta\,
# \partial v/\partial W$, and a small step along them moves $v$ towards the target
# $v + \delta$, i.e. lowers the per-sample energy $\frac12 (\text{target} - v)^2$.

# %%
cfg = dataclasses.replace(net.config, eps_q=1e-4, eps_w=1e-4)
net = Network.from_weights(cfg, net.W, net.Q)
for a in range(4):
    for delta in (0.7, -0.4):
        dQ, dW = net.increments(I, s, a, delta)
        gQ, gW = net.value_gradient(I, a)
        np.testing.assert_allclose(dQ, cfg.eps_q * delta * gQ, rtol=1e-12)
        np.testing.assert_allclose(dW, cfg.eps_w * delta / cfg.beta_s * gW, rtol=1e-12, atol=1e-18)
        target = net.value(I, a) + delta
        stepped = Network.from_weights(cfg, net.W + dW, net.Q + dQ)
        assert abs(target - stepped.value(I, a)) < abs(target - net.value(I, a))
print("increments = eps * delta * gradient (W: divided by beta_s); each step reduces the error.")

# %% [markdown]
# ## Check 3 — what the local rule keeps and what it loses
#
# The local rule drops the bracket: $\Delta W^\text{loc}_{jn} = \varepsilon_W \delta s_j I_n$
# versus $\Delta W^\text{nl}_{jn} = \varepsilon_W \delta s_j I_n c_j$ with
# $c_j = Q_{ij} - \sum_k Q_{ik} s_k$.  Both are outer products with the same $I$ and the same
# $\delta$, so the angle between them depends only on $s$ and $c$:
#
# $$\cos\angle(\Delta W^\text{loc}, \Delta W^\text{nl}) = \frac{\sum_j s_j^2 c_j}{\|s\|\,\|s \circ c\|} .$$
#
# The local rule **keeps** the $\delta$-modulated Hebbian term: every active unit moves towards
# the input when $\delta > 0$ and away from it when $\delta < 0$.  It **loses** the
# competitive term: which of the active units actually drives the chosen action.  A unit with
# $Q_{ij}$ below the $s$-weighted average $\sum_k Q_{ik}s_k$ should move the *other* way.
#
# Below: many random states at the paper's $\beta^s = 100$ (random feature weights, action
# weights uniform in $[0, 1]$, sparse random images, random chosen action).

# %% tags=["hide-input"]
cfg_nl = NetworkConfig(beta_s=100.0, rule="nonlocal")
cfg_loc = dataclasses.replace(cfg_nl, rule="local")
rng = np.random.default_rng(1)
cosines, winner_drives_action, norm_ratio = [], [], []
for _ in range(2000):
    net_nl = Network(cfg_nl, rng)
    net_nl.Q[:] = rng.random(net_nl.Q.shape)
    net_loc = Network.from_weights(cfg_loc, net_nl.W, net_nl.Q)
    I = net_nl.prepare(rng.random((10, 32)) * (rng.random((10, 32)) < 0.2))
    s = net_nl.features(I)
    a = int(rng.integers(4))
    _, dW_nl = net_nl.increments(I, s, a, 1.0)
    _, dW_loc = net_loc.increments(I, s, a, 1.0)
    cos = np.sum(dW_nl * dW_loc) / (np.linalg.norm(dW_nl) * np.linalg.norm(dW_loc))
    c = net_nl.Q[a] - net_nl.Q[a] @ s
    assert np.isclose(cos, np.sum(s**2 * c) / (np.linalg.norm(s) * np.linalg.norm(s * c)))
    cosines.append(cos)
    winner = int(np.argmax(s))
    winner_drives_action.append(net_nl.Q[a, winner] == net_nl.Q[a].max())
    norm_ratio.append(np.linalg.norm(dW_nl) / np.linalg.norm(dW_loc))
cosines = np.array(cosines)
winner_drives_action = np.array(winner_drives_action)

fig, ax = plt.subplots(figsize=(7, 3.2))
bins = np.linspace(-1, 1, 41)
ax.hist(
    cosines[winner_drives_action],
    bins,
    alpha=0.7,
    label="winner has the largest $Q_{ij}$ for the chosen action",
)
ax.hist(
    cosines[~winner_drives_action], bins, alpha=0.7, label="another unit drives the chosen action"
)
ax.set_xlabel(r"cos angle($\Delta W^{loc}$, $\Delta W^{nl}$)")
ax.set_ylabel("states")
ax.set_title(r"Local vs non-local update of $W$, $\beta^s = 100$, 4 feature units")
ax.legend(fontsize=8)
plt.show()

agree = np.mean(cosines[winner_drives_action] > 0)
disagree = np.mean(cosines[~winner_drives_action] < 0)
print(
    f"winner drives the action ({winner_drives_action.mean():.0%} of states): cos > 0 in {agree:.1%}"
)
print(f"otherwise: cos < 0 (local update points uphill) in {disagree:.1%}")
print(f"median |dW_nl| / |dW_loc| = {np.median(norm_ratio):.3f}")
assert agree > 0.95
assert disagree > 0.3

# %% [markdown]
# When the winning unit is the one that drives the chosen action (the typical situation once
# the policy is learned and acts greedily), the local update points into the same half-space as
# the gradient, so it still descends $E$.  Otherwise it points uphill (negative cosine) more
# often than not: the local rule then moves the features *up* the energy.  The non-local
# update is also much smaller
# (median ratio above): it is weighted by how undecided the feature layer is.
#
# **At a clear winner the non-local update vanishes** (Sec. II-B: "the first and the second term
# cancel each other out and learning has converged"), while the local one keeps pulling the
# winner's weights towards the input.

# %% tags=["hide-input"]
net_nl = Network(cfg_nl, np.random.default_rng(2))
net_nl.Q[:] = np.random.default_rng(3).random(net_nl.Q.shape)
net_loc = Network.from_weights(cfg_loc, net_nl.W, net_nl.Q)
I = net_nl.prepare(image)
for winner in range(4):
    s_onehot = np.eye(4)[winner]
    for a in range(4):
        _, dW_nl = net_nl.increments(I, s_onehot, a, 0.8)
        _, dW_loc = net_loc.increments(I, s_onehot, a, 0.8)
        assert np.all(dW_nl == 0.0)
        assert np.linalg.norm(dW_loc[winner]) > 0 and np.all(dW_loc[np.arange(4) != winner] == 0)
print("one-hot s: non-local update exactly 0; local update moves the winner's row only.")

# Near a clear winner the non-local update shrinks like the losers' total activity 1 - s_max.
for margin in (0.05, 0.1, 0.2):
    h = np.array([margin, 0.0, 0.0, 0.0])
    s_soft = np.exp(100 * h) / np.exp(100 * h).sum()  # Eq. (2) with beta_s = 100
    _, dW_nl = net_nl.increments(I, s_soft, 0, 1.0)
    _, dW_loc = net_loc.increments(I, s_soft, 0, 1.0)
    ratio = np.linalg.norm(dW_nl) / np.linalg.norm(dW_loc)
    print(
        f"h margin {margin:.2f}: 1 - s_max = {1 - s_soft.max():.1e}, |dW_nl|/|dW_loc| = {ratio:.1e}"
    )

# %% [markdown]
# ## Summary
#
# * Eq. (8) is $\delta$ times the exact gradient of $v$ with respect to $W$ (Eq. 16), up to the
#   factor $\beta^s$ that the paper absorbs into the learning rate; with the target held fixed
#   (Eq. 10–11) it is a stochastic (semi-)gradient step on the energy of Eq. (9), and the
#   rectification/normalization that follows is a Euclidean projection.  Checked symbolically
#   (SymPy), numerically (finite differences through `docking.network`, relative error
#   $< 10^{-5}$ at $\beta^s = 3$ and $100$), and by the sign of the resulting step.
# * The local rule keeps the $\delta$-gated Hebbian part and agrees in direction with the
#   gradient when the winning feature is the one that drives the chosen action; it loses the
#   competitive term and can point uphill otherwise.  At a clear winner the non-local update is
#   zero and the local one is not — with $\beta^s = 100$ the non-local rule therefore only
#   learns on inputs the feature layer is undecided about.
