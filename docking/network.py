"""The two-layer network of Kleesiek et al. (2011), Sec. II-A and II-B.

Input layer (pixels ``I``) -> softmax feature layer (weights ``W``, state ``s``) -> Q-value
action layer (weights ``Q``).  Both layers learn from the same SARSA prediction error delta.
Each of the paper's equations is written out once, in a comment at the line that computes it:

* Eq. (1)-(2), the feature layer: :meth:`Network.features`;
* Eq. (3)-(4), the action layer and the policy: :meth:`Network.action_probabilities`;
* Eq. (5), the value of the chosen action: :meth:`Network.value`;
* Eq. (7)-(8), the learning rules: :meth:`Network.update` (:meth:`Network.increments` returns
  the same changes without applying them), after which ``W`` is rectified (``W >= 0``) and each
  row normalized to unit length (Sec. II-A);
* Eq. (12) and (16), the exact gradient of Eq. (5): :meth:`Network.value_gradient`.

Eq. (6), the prediction error delta, is computed by :func:`docking.trial.run_trial`.

Sign convention: delta (Eq. 6) is the target minus the estimate, so every update adds
``eps * delta * dv/dtheta``, i.e. gradient *descent* on the energy of Eq. (9) (Eq. 11).

beta_s: Eq. (16) says "proportional to"; the exact derivative of ``v`` w.r.t. ``W`` carries an
extra factor ``beta_s`` (from the softmax of Eq. 2).  As in the paper, the learning rule
:meth:`Network.update` leaves it out (it is absorbed into ``eps_w``), whereas
:meth:`Network.value_gradient` returns the exact gradient including ``beta_s`` so that it can be
checked against finite differences.  The effective gradient step on ``W`` is ``eps_w / beta_s``.
Notebook 01 derives Eq. (9)-(16) and checks the code against them.

Only numpy is used.  All randomness comes from an explicitly passed ``numpy.random.Generator``.
"""

from __future__ import annotations

import dataclasses
import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from docking import arith
from docking.fileio import atomic_write
from docking.validate import (
    FieldTypeError,
    check_bool,
    check_choice,
    check_int,
    check_real,
    normalise,
)

__all__ = ["NetworkConfig", "Network", "RULES", "finite_difference_gradient"]

#: The two feature-layer learning rules: ``"nonlocal"`` is Eq. (8) as printed, with its bracket
#: (the gradient of Eq. 16); ``"local"`` drops the bracket, the "purely local learning rule" of
#: Sec. II-B.
RULES = ("local", "nonlocal")

#: ``"softmax"``: the paper's feature layer (Eq. 1-2); ``"none"``: ``s = I`` (linear SARSA).
FEATURE_LAYERS = ("softmax", "none", "winner")

_FORMAT_VERSION = 2

#: A row of W whose norm after rectification is at most this (rows had unit length before the
#: update) is treated as all-zero: its direction would be rounding noise.
_DEAD_NORM = 1e-12

#: Upper bound of the learning rates (eps_q, eps_w), q_init and |feature_delta|: far above
#: any rate that learns (the paper's are below 1). It does not keep every update finite: a
#: rate above the LMS bound (linear SARSA's eps_q above 2) can grow Q without limit, and a run
#: stops with an error when an update would make Q non-finite (the equal contest's amendment 1).
MAX_RATE = 100.0

#: Upper bound of the softmax gains beta_s, beta_a (the paper: 100); beyond it Eq. (2) and
#: (4) are a hard max to float precision anyway.
MAX_BETA = 1e6


@dataclass(frozen=True)
class NetworkConfig:
    """Sizes, inverse temperatures and learning rates of the network (one place for each fact).

    Attributes:
        n_inputs: number of input pixels; 320 = the 32x10 grayscale image of Sec. II-A.
        n_features: feature (hidden) units; the paper uses "either 4 or 36" (Sec. II-A).
        n_actions: action units; 4 = forward, backward, left, right (Sec. II-C).
        beta_s: inverse temperature of the feature softmax, Eq. (2); paper: 100
            ("winner-take-all-like").
        beta_a_train: inverse temperature of the action softmax, Eq. (4), during training;
            paper: 2 ("to make the agent explore").
        beta_a_test: inverse temperature of Eq. (4) during testing; paper: 100.
        gamma: discount factor of Eq. (6); paper: 0.9.
        eps_q: learning rate of the action weights, Eq. (7) (the paper only gives
            "proportional to"; 0.1 is our choice, calibrated against other values in
            notebooks 03 and 04, "What the choices do").
        eps_w: learning rate of the feature weights, Eq. (8) (not in the paper; 0.05 is our
            choice).  The factor beta_s of the exact gradient is absorbed into it.
        rule: "nonlocal" = Eq. (8) with its bracket; "local" = Eq. (8) without the
            bracket (Sec. II-B); see RULES.
        normalize_input: scale each input vector I to unit Euclidean length before Eq. (1)
            (an all-zero input stays zero).  Not in the paper; it makes h_j a cosine
            similarity in [0, 1] (rows of W have unit length too), so that beta_s = 100 has
            the same meaning whatever the brightness of the image.
        q_init: initial action weights are drawn uniform in [0, q_init].  0: all
            actions start equally likely and all values start at 0, the natural start for a
            reward in {0, 1}.  W is drawn first, and Q consumes the same number of draws
            whatever q_init (also 0), so q_init changes nothing else that the same
            generator produces.
        feature_delta: what modulates Eq. (8). None (the paper): the TD error delta of
            Eq. (6). A number c: Eq. (8) keeps its form with delta replaced by the
            constant c, an unmodulated control (competitive Hebbian feature learning
            alongside SARSA; Eq. 7 still uses delta).
        permute_delta: the permutation control of the modulation: Eq. (8) keeps its form,
            but the delta it uses is not this step's: it is drawn uniformly from the TD errors
            of the run's earlier training steps (DeltaShuffle),
            so it keeps delta's distribution (sign and size) and loses its correlation with
            the current input and learning progress (Eq. 7 still uses this step's delta).
            False: the paper. Excludes feature_delta.
        feature_layer: "softmax" (the paper, Eq. 1-2) or "none": no feature layer,
            s = I, a linear SARSA on the pixels (n_features must equal n_inputs;
            W is the identity and is never learned). "winner": the forced single winner,
            s one-hot at the unit of the largest h_j of Eq. (1) (beta_s unused): no
            population code at all. Eq. (8) is kept as written, so with s one-hot the
            non-local rule's bracket is 0 and W never changes, and the local rule moves the
            winner alone, by eps_w delta I (a delta-modulated competitive rule).
    """

    n_inputs: int = 320  # 32x10 image, Sec. II-A
    n_features: int = 4  # "either 4 or 36", Sec. II-A
    n_actions: int = 4  # forward, backward, left, right, Sec. II-C
    beta_s: float = 100.0  # Eq. (2)
    beta_a_train: float = 2.0  # Eq. (4), training
    beta_a_test: float = 100.0  # Eq. (4), testing
    gamma: float = 0.9  # Eq. (6)
    eps_q: float = 0.1  # learning rate of Eq. (7); not in the paper
    eps_w: float = 0.05  # learning rate of Eq. (8); not in the paper
    rule: str = "nonlocal"  # Eq. (8) with its bracket; "local" drops it
    normalize_input: bool = True  # unit-length I before Eq. (1); not in the paper
    q_init: float = 0.0  # Q ~ U[0, q_init]; not in the paper
    feature_delta: float | None = None  # None: Eq. (8) uses delta; a number: that constant
    feature_layer: str = "softmax"  # Eq. (1)-(2); "none": linear SARSA on the pixels
    permute_delta: bool = False  # True: Eq. (8) uses an earlier step's delta (a control)

    def __post_init__(self) -> None:
        owner = "NetworkConfig"
        counts = {
            name: check_int(owner, name, getattr(self, name), lo=1, hi=1_000_000)
            for name in ("n_inputs", "n_features", "n_actions")
        }
        reals = {
            name: check_real(owner, name, getattr(self, name), lo=0, hi=MAX_BETA, lo_open=True)
            for name in ("beta_s", "beta_a_train", "beta_a_test")
        }
        reals["gamma"] = check_real(owner, "gamma", self.gamma, lo=0, hi=1)
        for name in ("eps_q", "eps_w", "q_init"):
            reals[name] = check_real(owner, name, getattr(self, name), lo=0, hi=MAX_RATE)
        normalise(
            self,
            **counts,
            **reals,
            rule=check_choice(owner, "rule", self.rule, RULES),
            normalize_input=check_bool(owner, "normalize_input", self.normalize_input),
            feature_layer=check_choice(owner, "feature_layer", self.feature_layer, FEATURE_LAYERS),
            permute_delta=check_bool(owner, "permute_delta", self.permute_delta),
        )
        if self.permute_delta and self.feature_delta is not None:
            raise ValueError(
                "NetworkConfig.permute_delta and feature_delta exclude each other (Eq. 8 is "
                f"modulated by one of them), got feature_delta={self.feature_delta!r}"
            )
        if self.feature_delta is not None:
            normalise(
                self,
                feature_delta=check_real(
                    owner, "feature_delta", self.feature_delta, lo=-MAX_RATE, hi=MAX_RATE
                ),
            )
        if self.feature_layer == "none" and self.n_features != self.n_inputs:
            raise ValueError(
                f"NetworkConfig.n_features must equal n_inputs ({self.n_inputs}) without a "
                f"feature layer (feature_layer='none'), got {self.n_features}"
            )


def _softmax(z: np.ndarray) -> np.ndarray:
    """Numerically stable softmax of a 1-D array of (already scaled) activations.

    Subtracts the maximum before exponentiating, so nothing overflows.  If the maximum itself
    is infinite (e.g. a huge beta times a huge input), the limit is returned: uniform over the
    maximal entries.  NaN in ``z`` raises ValueError.
    """
    # Python-level max/sum: on arrays of a few dozen entries they are faster than numpy's.
    zmax = max(z.tolist())
    if math.isfinite(zmax):
        e = arith.exp(z - zmax)
        # math.fsum: exactly rounded, so the same on every Python (the builtin sum() of
        # floats is compensated from 3.12 on and naive before).
        total = math.fsum(e.tolist())  # >= 1: the max entry contributes exp(0)
        if total >= 1.0:  # False only if z holds NaN (which max() may skip)
            e *= 1.0 / total
            return e
    if np.isnan(z).any():
        raise ValueError("softmax input contains NaN (non-finite input or weights)")
    top = (z == zmax).astype(np.float64)
    return top / top.sum()


class Network:
    """Feature layer ``W`` (n_features x n_inputs) and action layer ``Q`` (n_actions x n_features).

    ``W`` starts non-negative uniform random with unit-length rows; ``Q`` uniform in
    ``[0, q_init]``.  All methods except :meth:`prepare` take the prepared input ``I`` (a flat
    float64 vector of length ``n_inputs``, see :meth:`prepare`).
    """

    W: np.ndarray
    Q: np.ndarray
    config: NetworkConfig

    def __init__(self, config: NetworkConfig, rng: np.random.Generator):
        if not isinstance(config, NetworkConfig):
            raise ValueError(f"config must be a NetworkConfig, got {type(config).__name__}")
        if not isinstance(rng, np.random.Generator):
            raise ValueError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
        self.config = config
        if config.feature_layer == "none":  # s = I: W is the identity, drawn from nothing
            self.W = np.eye(config.n_inputs)
        else:
            W = rng.random((config.n_features, config.n_inputs))
            # A row of zeros has probability 0 but would be a dead unit: guard anyway.
            W[np.all(W == 0, axis=1)] = 1.0
            self.W = W / np.sqrt(arith.rowdot(W, W))[:, None]
        self.Q = rng.uniform(0.0, config.q_init, (config.n_actions, config.n_features))

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_weights(cls, config: NetworkConfig, W, Q) -> Network:
        """A network with the given weights (copied, as float64); checks shapes and finiteness.

        ``W`` is used as given (not rectified/normalized); this is for tests, loading and
        hand-made examples.
        """
        if not isinstance(config, NetworkConfig):
            raise ValueError(f"config must be a NetworkConfig, got {type(config).__name__}")
        W = np.array(W, dtype=np.float64)
        Q = np.array(Q, dtype=np.float64)
        if W.shape != (config.n_features, config.n_inputs):
            raise ValueError(
                f"W must have shape {(config.n_features, config.n_inputs)}, got {W.shape}"
            )
        if Q.shape != (config.n_actions, config.n_features):
            raise ValueError(
                f"Q must have shape {(config.n_actions, config.n_features)}, got {Q.shape}"
            )
        if not (np.isfinite(W).all() and np.isfinite(Q).all()):
            raise ValueError("W and Q must be finite")
        net = cls.__new__(cls)
        net.config = config
        net.W = W
        net.Q = Q
        return net

    def copy(self) -> Network:
        """An independent deep copy (same config, copied weights)."""
        return Network.from_weights(self.config, self.W, self.Q)

    # ------------------------------------------------------------------ forward pass
    def prepare(self, observation) -> np.ndarray:
        """The network input ``I`` for an observation: flat float64 copy, unit length if
        ``config.normalize_input`` (an all-zero observation stays zero).

        Any shape with ``n_inputs`` elements is accepted (e.g. the (10, 32) camera image,
        flattened row-major).  Raises ValueError for a wrong size or non-finite values.
        """
        I = np.array(observation, dtype=np.float64).reshape(-1)  # always a fresh copy
        if I.size != self.config.n_inputs:
            raise ValueError(
                f"observation must have {self.config.n_inputs} elements, got "
                f"{I.size} (shape {np.shape(observation)})"
            )
        sq = arith.dot(I, I)
        if not math.isfinite(sq):  # NaN/inf in the input, or squares overflowing
            if not np.isfinite(I).all():
                raise ValueError("observation contains NaN or infinite values")
            if self.config.normalize_input:
                I /= np.abs(I).max()
                sq = arith.dot(I, I)
        if self.config.normalize_input and sq > 0:
            I /= np.sqrt(sq)
        return I

    def features(self, I: np.ndarray) -> np.ndarray:
        """Feature-layer state ``s`` of the prepared input ``I``, Eq. (1)-(2).

        Stable for any finite input: all-zero input gives uniform ``s``; overflowing
        activations give the hard-max limit.
        """
        self._check_vector(I, self.config.n_inputs, "I")
        if self.config.feature_layer == "none":
            return I  # no feature layer: linear SARSA on the pixels
        # Eq. (1): h_j = sum_n W_jn I_n
        h = arith.matvec(self.W, I)
        if self.config.feature_layer == "winner":  # the forced single winner, not Eq. (2)
            s = np.zeros_like(h)
            s[int(np.argmax(h))] = 1.0  # the first of tied units
            return s
        # Eq. (2): s_j = exp(beta_s h_j) / sum_k exp(beta_s h_k)
        return _softmax(self.config.beta_s * h)

    def action_probabilities(self, s: np.ndarray, beta_a: float) -> np.ndarray:
        """The policy: the probability of each action for the feature state ``s``, Eq. (3)-(4).

        ``beta_a >= 0`` (0 gives the uniform random policy).
        """
        beta_a = check_real("Network", "beta_a", beta_a, lo=0)
        self._check_vector(s, self.config.n_features, "s")
        # Eq. (3): h_i = sum_j Q_ij s_j
        # Eq. (4): P(a_i = 1) = exp(beta_a h_i) / sum_k exp(beta_a h_k)
        return _softmax(beta_a * arith.matvec(self.Q, s))

    def select_action(self, s: np.ndarray, rng: np.random.Generator, beta_a: float) -> int:
        """Sample an action index from Eq. (4), using one ``rng.random()`` draw."""
        if not isinstance(rng, np.random.Generator):
            raise FieldTypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
        p = self.action_probabilities(s, beta_a).tolist()
        u = rng.random() * math.fsum(p)
        last = len(p) - 1
        acc = 0.0
        for a in range(last):
            acc += p[a]
            if u < acc:
                return a
        return last

    def value(self, I: np.ndarray, a: int) -> float:
        """The value of action ``a`` for the prepared input ``I``, Eq. (5)."""
        self._check_action(a)
        return arith.dot(self.Q[a], self.features(I))  # Eq. (5): v = sum_kl Q_kl a_k s_l, a one-hot

    def value_gradient(self, I: np.ndarray, a: int) -> tuple[np.ndarray, np.ndarray]:
        """Exact gradient of ``v(I, a)`` (Eq. 5) w.r.t. ``Q`` and ``W``.

        Returns ``(dQ, dW)``, Eq. (12) and Eq. (16).  Eq. (16) is written "proportional to" and
        omits the factor ``beta_s`` that the chain rule through the softmax of Eq. (2) produces;
        this method includes it, so it is the exact derivative (it matches finite
        differences).  :meth:`update` omits it, as the paper does (absorbed into ``eps_w``).
        """
        self._check_action(a)
        s = self.features(I)
        dQ = np.zeros_like(self.Q)
        dQ[a] = s  # Eq. (12): dv/dQ_ij = a_i s_j
        if self.config.feature_layer == "none":  # v = Q[a] . I does not depend on W
            return dQ, np.zeros_like(self.W)
        q = self.Q[a]
        # Eq. (16), times beta_s: dv/dW_jn = beta_s s_j I_n (Q_ij - sum_k Q_ik s_k), i = a
        dW = np.multiply.outer(self.config.beta_s * s * (q - arith.dot(q, s)), I)
        return dQ, dW

    # ------------------------------------------------------------------ learning
    def _feature_factor(self, s: np.ndarray, a: int) -> np.ndarray:
        """Per unit ``j``, the factor of Eq. (8) that is neither delta nor the input: ``s_j``
        times the bracket for the non-local rule, ``s_j`` alone for the local rule (with the
        current, i.e. pre-update, Q)."""
        if self.config.rule == "nonlocal":
            q = self.Q[a]
            return s * (q - arith.dot(q, s))  # s_j times the bracket of Eq. (8)
        return s  # the local rule: Eq. (8) without the bracket

    def increments(
        self, I: np.ndarray, s: np.ndarray, a: int, delta: float, feature_delta=None
    ) -> tuple[np.ndarray, np.ndarray]:
        """The raw weight changes ``(Delta Q, Delta W)`` of Eq. (7) and (8) for the configured
        rule, as :meth:`update` computes them, before W is rectified and normalized; nothing is
        modified.  For the non-local rule
        ``Delta W = (eps_w delta / beta_s) * value_gradient(I, a)[1]`` when ``s = features(I)``.
        """
        self._check_step(I, s, a, delta)
        cfg = self.config
        feature_delta = self._feature_delta(delta, feature_delta)
        dQ = np.zeros_like(self.Q)
        dQ[a] = (cfg.eps_q * delta) * s  # Eq. (7), see update()
        if cfg.feature_layer == "none":
            return dQ, np.zeros_like(self.W)
        dW = np.multiply.outer(self._feature_factor(s, a) * (cfg.eps_w * feature_delta), I)
        return dQ, dW  # Eq. (8), see update()

    def update(
        self, I: np.ndarray, s: np.ndarray, a: int, delta: float, feature_delta=None
    ) -> None:
        """One learning step from input ``I``, its state ``s = features(I)``, the chosen action
        ``a`` and the TD error ``delta`` (Eq. 6), in place. ``feature_delta``: the permuted
        delta Eq. (8) uses in the permutation control (``config.permute_delta``; required
        there, refused otherwise).

        * Eq. (7) on the chosen action's row of Q.
        * Eq. (8) on W, with the *pre-update* Q in its bracket (``rule="local"``: without the
          bracket).  No factor beta_s (absorbed into eps_w, see the module docstring).  These
          are the increments returned by :meth:`increments`.
        * Then W is rectified (``W >= 0``) and every row scaled to unit length (Sec. II-A).
          A row that the update would make exactly zero (all weights pushed to <= 0) cannot be
          normalized; that row keeps its previous (unit-length, non-negative) value, i.e. the
          update is rejected for that unit only.  Rows never become NaN.
        """
        self._check_step(I, s, a, delta)
        cfg = self.config
        feature_delta = self._feature_delta(delta, feature_delta)
        # Eq. (8): Delta W_jn = eps_w delta s_j I_n (Q_ij - sum_k Q_ik s_k), i = the chosen
        # action a (delta: the constant feature_delta in the unmodulated control); its
        # coefficient per unit j is taken before Q changes.
        coef = self._feature_factor(s, a) * (cfg.eps_w * feature_delta)
        q_row = self.Q[a] + (cfg.eps_q * delta) * s  # Eq. (7): Delta Q_ij = eps_q delta a_i s_j
        if not np.isfinite(q_row).all():
            raise ValueError(
                f"the update would make Q non-finite (delta={delta!r}); nothing changed"
            )
        if cfg.feature_layer == "none":  # nothing else to learn
            self.Q[a] = q_row
            return
        # Apply Eq. (8), then rectify and normalize rows (Sec. II-A).
        Wn = np.multiply.outer(coef, I)
        Wn += self.W
        np.maximum(Wn, 0.0, out=Wn)
        norms = np.sqrt(arith.rowdot(Wn, Wn))
        nl = norms.tolist()
        if not (np.isfinite(norms).all() and min(nl) > _DEAD_NORM):  # rare: fix rows one by one
            for j, norm in enumerate(nl):
                if not _DEAD_NORM < norm < math.inf:  # False also for NaN
                    norms[j] = self._fix_row(Wn, j)
        self.Q[a] = q_row  # nothing can fail from here on: the update is whole or not at all
        np.divide(Wn, norms[:, None], out=self.W)

    def _feature_delta(self, delta: float, permuted) -> float:
        """The factor that modulates Eq. (8): delta, the control's constant, or the permuted
        delta given by the caller."""
        cfg = self.config
        if cfg.permute_delta != (permuted is not None):
            raise ValueError(
                "Network.update: a permuted feature_delta is required exactly when "
                f"config.permute_delta (here {cfg.permute_delta}), got {permuted!r}"
            )
        if permuted is not None:
            return check_real("Network", "feature_delta", permuted)
        return delta if cfg.feature_delta is None else cfg.feature_delta

    def som_update(self, I: np.ndarray, rate: float, sigma: float) -> int:
        """Kohonen's self-organizing map, without delta (the first stage of a two-stage
        learner, the kind the paper's Sec. IV names): the feature units sit on the grid
        :meth:`som_grid`; the unit ``j`` with the largest ``h_j`` (Eq. 1) wins, and every unit
        ``k`` moves towards the input, ``W_k += rate g_k (I - W_k)``, with the neighbourhood
        ``g_k = exp(-d(j, k)^2 / (2 sigma^2))`` of its grid distance to the winner; rows are
        then rectified and normalized like every row of W. An all-zero input changes
        nothing. Returns the winner (-1 for an all-zero input)."""
        self._check_vector(I, self.config.n_inputs, "I")
        rate = check_real("Network", "rate", rate, lo=0, hi=1)
        sigma = check_real("Network", "sigma", sigma, lo=0, lo_open=True, hi=MAX_RATE)
        if self.config.feature_layer == "none" or not I.any():
            return -1
        j = int(np.argmax(arith.matvec(self.W, I)))  # Eq. (1), the winner of Eq. (2)'s softmax
        rows, cols = self.som_grid(self.config.n_features)
        k = np.arange(self.config.n_features)
        d2 = (k // cols - j // cols) ** 2 + (k % cols - j % cols) ** 2
        g = arith.exp(-d2 / (2.0 * sigma * sigma))
        Wn = np.maximum(self.W + (rate * g)[:, None] * (I - self.W), 0.0)
        for u in range(self.config.n_features):
            norm = math.sqrt(arith.dot(Wn[u], Wn[u]))
            if norm > _DEAD_NORM:
                self.W[u] = Wn[u] / norm
        return j

    @staticmethod
    def som_grid(n_features: int) -> tuple[int, int]:
        """The ``(rows, cols)`` grid of :meth:`som_update`'s units, in row-major order: the
        most nearly square factorisation of ``n_features`` (36: 6x6, 4: 2x2)."""
        rows = max(r for r in range(1, math.isqrt(n_features) + 1) if n_features % r == 0)
        return rows, n_features // rows

    def competitive_update(self, I: np.ndarray, rate: float) -> int:
        """Winner-take-all competitive learning, without delta (not the paper's rule; the
        first stage of the two-stage learner its Sec. IV names): the unit ``j`` with the
        largest ``h_j`` (Eq. 1) moves towards the input, ``W_j += rate (I - W_j)``, and is
        rectified and normalized like every row of W. An all-zero input changes nothing.
        Returns the winner (-1 for an all-zero input)."""
        self._check_vector(I, self.config.n_inputs, "I")
        rate = check_real("Network", "rate", rate, lo=0, hi=1)
        if self.config.feature_layer == "none" or not I.any():
            return -1
        j = int(np.argmax(arith.matvec(self.W, I)))  # Eq. (1), the winner of Eq. (2)'s softmax
        row = np.maximum(self.W[j] + rate * (I - self.W[j]), 0.0)
        norm = math.sqrt(arith.dot(row, row))
        if norm > _DEAD_NORM:
            self.W[j] = row / norm
        return j

    def _fix_row(self, Wn: np.ndarray, j: int) -> float:
        """Make row ``j`` of the rectified candidate ``Wn`` normalizable; return its norm.

        A row whose squared entries overflow is rescaled by its maximum first.  A row that is
        (numerically) zero, i.e. norm <= ``_DEAD_NORM`` of a row that had unit length, or that
        holds non-finite values (``|delta|`` so large that the update overflowed), gets its
        previous value back.
        """
        row = Wn[j]
        if np.isfinite(row).all():
            m = row.max()
            if m > _DEAD_NORM:  # finite entries whose squares overflowed: rescale first
                row /= m
                return math.sqrt(arith.dot(row, row))
        row[:] = self.W[j]  # keep the previous row (unit length, non-negative)
        return math.sqrt(arith.dot(row, row))

    def _check_action(self, a) -> None:
        if (
            isinstance(a, (bool, np.bool_))
            or not isinstance(a, (int, np.integer))
            or not 0 <= a < self.config.n_actions
        ):
            raise ValueError(
                f"action a must be an integer in [0, {self.config.n_actions}), got {a!r}"
            )

    @staticmethod
    def _check_vector(x, size: int, name: str) -> None:
        """``x`` must be a finite float ndarray of shape ``(size,)``."""
        if not isinstance(x, np.ndarray) or x.shape != (size,) or x.dtype.kind != "f":
            raise ValueError(
                f"{name} must be a float ndarray of shape ({size},) (see Network.prepare), got "
                f"{type(x).__name__} {getattr(x, 'dtype', '')} {np.shape(x)}"
            )
        if not np.isfinite(x).all():
            raise ValueError(f"{name} contains NaN or infinite values")

    def _check_step(self, I, s, a, delta) -> None:
        """Everything a learning step reads, checked before anything changes."""
        self._check_action(a)
        self._check_vector(I, self.config.n_inputs, "I")
        self._check_vector(s, self.config.n_features, "s")
        check_real("Network", "delta", delta)

    # ------------------------------------------------------------------ persistence
    def save(self, path) -> None:
        """Write ``W``, ``Q`` and every config field to ``path`` (.npz, exactly that name).

        Atomic (:func:`docking.fileio.atomic_write`).
        """
        path = Path(path)
        arrays = {
            "W": self.W,
            "Q": self.Q,
            "format_version": np.array(_FORMAT_VERSION),
            "config": np.array(json.dumps(dataclasses.asdict(self.config))),
        }
        atomic_write(path, lambda f: np.savez(f, **arrays))

    @classmethod
    def load(cls, path) -> Network:
        """Read a network written by :meth:`save` (format 2; format 1 stored one array per
        config field)."""
        path = Path(path)
        try:
            with np.load(path, allow_pickle=False) as data:
                version = int(data["format_version"])
                if version == 2:
                    config = NetworkConfig(**json.loads(str(data["config"])))
                elif version == 1:
                    fields = [f.name for f in dataclasses.fields(NetworkConfig)]
                    config = NetworkConfig(
                        **{f: data[f"config.{f}"].item() for f in fields if f"config.{f}" in data}
                    )
                else:
                    raise ValueError(f"unsupported network file format_version {version}")
                return cls.from_weights(config, data["W"], data["Q"])
        except OSError:  # missing or unreadable: the exception names the path already
            raise
        except Exception as exc:  # empty, truncated, not a zip, a field missing, ...
            raise ValueError(
                f"{str(path)!r} is not a network file written by Network.save "
                f"({type(exc).__name__}: {exc})"
            ) from exc

    def __repr__(self) -> str:
        c = self.config
        return (
            f"Network(n_inputs={c.n_inputs}, n_features={c.n_features}, "
            f"n_actions={c.n_actions}, rule={c.rule!r})"
        )


def finite_difference_gradient(
    net: Network, I: np.ndarray, a: int, h: float = 1e-6
) -> tuple[np.ndarray, np.ndarray]:
    """Central-difference estimate ``(dv/dQ, dv/dW)`` of :meth:`Network.value` ``(I, a)``:
    ``(v(theta + h e) - v(theta - h e)) / 2h`` for every entry ``e`` of ``Q`` and ``W``.

    Independent of :meth:`Network.value_gradient` (it only evaluates Eq. 5), so the two can
    check each other. ``net`` is restored exactly afterwards.
    """
    grads = []
    for param in (net.Q, net.W):
        g = np.zeros_like(param)
        for idx in np.ndindex(param.shape):
            old = param[idx]
            param[idx] = old + h
            up = net.value(I, a)
            param[idx] = old - h
            down = net.value(I, a)
            param[idx] = old
            g[idx] = (up - down) / (2 * h)
        grads.append(g)
    return grads[0], grads[1]
