"""The two-layer network of Kleesiek et al. (2011), Sec. II-A and II-B.

Input layer (pixels ``I``) -> softmax feature layer (weights ``W``, state ``s``) -> Q-value
action layer (weights ``Q``).  Both layers learn from the same SARSA prediction error delta:

* Eq. (1)-(2): ``h_j = sum_n W_jn I_n``,  ``s = softmax(beta_s * h)``
* Eq. (3)-(4): ``h_i = sum_j Q_ij s_j``,  ``P(a_i = 1) = softmax(beta_a * h)_i``
* Eq. (5):     ``v = sum_kl Q_kl a_k s_l = Q[a] . s``  (``a`` one-hot)
* Eq. (7):     ``Delta Q_ij = eps_q * delta * a_i * s_j``
* Eq. (8):     ``Delta W_jn = eps_w * delta * s_j * I_n * (Q_ij - sum_k Q_ik s_k)``
               (``i`` = the chosen action)

after which ``W`` is rectified (``W >= 0``) and each row normalized to unit length (Sec. II-A).
:meth:`Network.increments` returns the raw changes of Eq. (7)-(8), :meth:`Network.update`
applies them.

Sign convention: ``delta = r + gamma v' - v`` (Eq. 6) is the target minus the estimate, so every
update is ``+ eps * delta * dv/dtheta``, i.e. gradient *descent* on the energy of Eq. (9)
(Eq. 11: ``-dE/dtheta = delta dv/dtheta``).

beta_s: Eq. (16) says "proportional to"; the exact derivative of ``v`` w.r.t. ``W_jn`` carries an
extra factor ``beta_s`` (from ``dh -> beta_s dh`` inside the softmax).  As in the paper, the
learning rule :meth:`Network.update` leaves it out (it is absorbed into ``eps_w``), whereas
:meth:`Network.value_gradient` returns the exact gradient including ``beta_s`` so that it can be
checked against finite differences.  The effective gradient step on ``W`` is ``eps_w / beta_s``.

Only numpy is used.  All randomness comes from an explicitly passed ``numpy.random.Generator``.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

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

#: The two feature-layer learning rules: ``"nonlocal"`` is Eq. (8)/(16) with the bracket
#: ``(Q_ij - sum_k Q_ik s_k)``; ``"local"`` drops the bracket (``delta s_j I_n``), the
#: "purely local learning rule" of Sec. II-B.
RULES = ("local", "nonlocal")

_FORMAT_VERSION = 1

#: A row of W whose norm after rectification is at most this (rows had unit length before the
#: update) is treated as all-zero: its direction would be rounding noise.
_DEAD_NORM = 1e-12


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
            "proportional to"; 0.1 is our choice: in both experiments 0.05 learned too slowly
            within the paper's trial counts and 0.2 or 0.5 let the greedy policy flip from
            evaluation to evaluation, see notebooks 03 and 04).
        eps_w: learning rate of the feature weights, Eq. (8) (not in the paper; 0.05 is our
            choice).  The factor beta_s of the exact gradient is absorbed into it.
        rule: ``"nonlocal"`` = Eq. (8)/(16) with the bracket ``(Q_ij - sum_k Q_ik s_k)``;
            ``"local"`` = drop the bracket, ``Delta W_jn = eps_w delta s_j I_n`` (Sec. II-B).
        normalize_input: scale each input vector ``I`` to unit Euclidean length before Eq. (1)
            (an all-zero input stays zero).  Not in the paper; it makes ``h_j`` a cosine
            similarity in [0, 1] (rows of W have unit length too), so that beta_s = 100 has
            the same meaning whatever the brightness of the image.
        q_init: initial action weights are drawn uniform in ``[0, q_init]``.  Default 0: all
            actions start equally likely and all values start at 0, the natural start for a
            reward in {0, 1}.  W is drawn first, and Q consumes the same number of draws
            whatever q_init (also 0), so q_init changes nothing else that the same
            generator produces.
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
    rule: str = "nonlocal"  # Eq. (8)/(16) with bracket; "local" drops it
    normalize_input: bool = True  # unit-length I before Eq. (1); not in the paper
    q_init: float = 0.0  # Q ~ U[0, q_init]; not in the paper

    def __post_init__(self) -> None:
        owner = "NetworkConfig"
        counts = {
            name: check_int(owner, name, getattr(self, name), lo=1, hi=1_000_000)
            for name in ("n_inputs", "n_features", "n_actions")
        }
        reals = {
            name: check_real(owner, name, getattr(self, name), lo=0, lo_open=True)
            for name in ("beta_s", "beta_a_train", "beta_a_test")
        }
        reals["gamma"] = check_real(owner, "gamma", self.gamma, lo=0, hi=1)
        for name in ("eps_q", "eps_w", "q_init"):
            reals[name] = check_real(owner, name, getattr(self, name), lo=0)
        normalise(
            self,
            **counts,
            **reals,
            rule=check_choice(owner, "rule", self.rule, RULES),
            normalize_input=check_bool(owner, "normalize_input", self.normalize_input),
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
        e = np.exp(z - zmax)
        total = sum(e.tolist())  # >= 1: the max entry contributes exp(0)
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
        W = rng.random((config.n_features, config.n_inputs))
        # A row of zeros has probability 0 but would be a dead unit: guard anyway.
        W[np.all(W == 0, axis=1)] = 1.0
        self.W = W / np.linalg.norm(W, axis=1, keepdims=True)
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
        sq = I @ I
        if not math.isfinite(sq):  # NaN/inf in the input, or squares overflowing
            if not np.isfinite(I).all():
                raise ValueError("observation contains NaN or infinite values")
            if self.config.normalize_input:
                I /= np.abs(I).max()
                sq = I @ I
        if self.config.normalize_input and sq > 0:
            I /= np.sqrt(sq)
        return I

    def features(self, I: np.ndarray) -> np.ndarray:
        """Feature-layer state ``s``: Eq. (1) ``h = W I`` and Eq. (2) ``s = softmax(beta_s h)``.

        Stable for any finite input: all-zero input gives uniform ``s``; overflowing
        activations give the hard-max limit.
        """
        self._check_vector(I, self.config.n_inputs, "I")
        return _softmax(self.config.beta_s * (self.W @ I))  # Eq. (1), (2)

    def action_probabilities(self, s: np.ndarray, beta_a: float) -> np.ndarray:
        """Eq. (3) ``h = Q s`` and Eq. (4) ``P(a_i = 1) = softmax(beta_a h)_i``.

        ``beta_a >= 0`` (0 gives the uniform random policy).
        """
        beta_a = check_real("Network", "beta_a", beta_a, lo=0)
        self._check_vector(s, self.config.n_features, "s")
        return _softmax(beta_a * (self.Q @ s))  # Eq. (3), (4)

    def select_action(self, s: np.ndarray, rng: np.random.Generator, beta_a: float) -> int:
        """Sample an action index from Eq. (4), using one ``rng.random()`` draw."""
        if not isinstance(rng, np.random.Generator):
            raise FieldTypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
        p = self.action_probabilities(s, beta_a).tolist()
        u = rng.random() * sum(p)
        last = len(p) - 1
        acc = 0.0
        for a in range(last):
            acc += p[a]
            if u < acc:
                return a
        return last

    def value(self, I: np.ndarray, a: int) -> float:
        """Eq. (5): ``v = sum_kl Q_kl a_k s_l = Q[a] . s(I)`` for the one-hot action ``a``."""
        self._check_action(a)
        return float(self.Q[a] @ self.features(I))  # Eq. (5)

    def value_gradient(self, I: np.ndarray, a: int) -> tuple[np.ndarray, np.ndarray]:
        """Exact gradient of ``v(I, a)`` (Eq. 5) w.r.t. ``Q`` and ``W``.

        Returns ``(dQ, dW)`` with
        ``dQ_ij = a_i s_j`` (Eq. 12) and
        ``dW_jn = beta_s * s_j * I_n * (Q_aj - sum_k Q_ak s_k)`` (Eq. 16).

        Eq. (16) is written "proportional to" and omits the factor ``beta_s`` that the chain
        rule through ``s = softmax(beta_s h)`` produces; this method includes it, so it is the
        exact derivative (it matches finite differences).  :meth:`update` omits it, as the
        paper does (absorbed into ``eps_w``).
        """
        self._check_action(a)
        s = self.features(I)
        dQ = np.zeros_like(self.Q)
        dQ[a] = s  # Eq. (12)
        q = self.Q[a]
        dW = np.multiply.outer(self.config.beta_s * s * (q - q @ s), I)  # Eq. (16) times beta_s
        return dQ, dW

    # ------------------------------------------------------------------ learning
    def _feature_factor(self, s: np.ndarray, a: int) -> np.ndarray:
        """Per-unit factor of Eq. (8) without delta and I: ``s_j (Q_aj - sum_k Q_ak s_k)`` for
        the non-local rule, ``s_j`` for the local rule (current, i.e. pre-update, Q)."""
        if self.config.rule == "nonlocal":
            q = self.Q[a]
            return s * (q - q @ s)  # Eq. (8)/(16): s_j (Q_ij - sum_k Q_ik s_k)
        return s  # local rule: Eq. (8) without the bracket

    def increments(
        self, I: np.ndarray, s: np.ndarray, a: int, delta: float
    ) -> tuple[np.ndarray, np.ndarray]:
        """The raw weight changes ``(Delta Q, Delta W)`` of Eq. (7) and (8) for the configured
        rule, before W is rectified and normalized; nothing is modified.

        ``Delta Q_ij = eps_q delta a_i s_j`` (Eq. 7);
        ``Delta W_jn = eps_w delta s_j I_n (Q_aj - sum_k Q_ak s_k)`` (Eq. 8, non-local) or
        ``eps_w delta s_j I_n`` (local).  For the non-local rule
        ``Delta W = (eps_w delta / beta_s) * value_gradient(I, a)[1]`` when ``s = features(I)``.
        """
        self._check_step(I, s, a, delta)
        cfg = self.config
        dQ = np.zeros_like(self.Q)
        dQ[a] = (cfg.eps_q * delta) * s  # Eq. (7)
        dW = np.multiply.outer(self._feature_factor(s, a) * (cfg.eps_w * delta), I)  # Eq. (8)
        return dQ, dW

    def update(self, I: np.ndarray, s: np.ndarray, a: int, delta: float) -> None:
        """One learning step from input ``I``, its state ``s = features(I)``, the chosen action
        ``a`` and the TD error ``delta`` (Eq. 6), in place.

        * Eq. (7): ``Q[a] += eps_q * delta * s``.
        * Eq. (8), ``rule="nonlocal"``:
          ``W_jn += eps_w * delta * s_j * I_n * (Q_aj - sum_k Q_ak s_k)``
          with the *pre-update* Q; ``rule="local"``: ``W_jn += eps_w * delta * s_j * I_n``.
          No factor beta_s (absorbed into eps_w, see the module docstring).  These are the
          increments returned by :meth:`increments`.
        * Then W is rectified (``W >= 0``) and every row scaled to unit length (Sec. II-A).
          A row that the update would make exactly zero (all weights pushed to <= 0) cannot be
          normalized; that row keeps its previous (unit-length, non-negative) value, i.e. the
          update is rejected for that unit only.  Rows never become NaN.
        """
        self._check_step(I, s, a, delta)
        cfg = self.config
        coef = self._feature_factor(s, a) * (cfg.eps_w * delta)  # before Q changes
        q_row = self.Q[a] + (cfg.eps_q * delta) * s  # Eq. (7): Delta Q_ij = eps_q delta a_i s_j
        if not math.isfinite(sum(q_row.tolist())):
            raise ValueError(
                f"the update would make Q non-finite (delta={delta!r}); nothing changed"
            )
        # Eq. (8), then rectify and normalize rows (Sec. II-A).
        Wn = np.multiply.outer(coef, I)
        Wn += self.W
        np.maximum(Wn, 0.0, out=Wn)
        norms = np.sqrt(np.einsum("ij,ij->i", Wn, Wn))
        nl = norms.tolist()
        if not (math.isfinite(sum(nl)) and min(nl) > _DEAD_NORM):  # rare: fix rows one by one
            for j, norm in enumerate(nl):
                if not _DEAD_NORM < norm < math.inf:  # False also for NaN
                    norms[j] = self._fix_row(Wn, j)
        self.Q[a] = q_row  # nothing can fail from here on: the update is whole or not at all
        np.divide(Wn, norms[:, None], out=self.W)

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
                return float(np.sqrt(row @ row))
        row[:] = self.W[j]  # keep the previous row (unit length, non-negative)
        return float(np.sqrt(row @ row))

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
        arrays = {"W": self.W, "Q": self.Q, "format_version": np.array(_FORMAT_VERSION)}
        for field in dataclasses.fields(NetworkConfig):
            arrays[f"config.{field.name}"] = np.array(getattr(self.config, field.name))
        atomic_write(path, lambda f: np.savez(f, **arrays))

    @classmethod
    def load(cls, path) -> Network:
        """Read a network written by :meth:`save`."""
        with np.load(Path(path), allow_pickle=False) as data:
            version = int(data["format_version"])
            if version != _FORMAT_VERSION:
                raise ValueError(f"unsupported network file format_version {version}")
            kwargs = {}
            for field in dataclasses.fields(NetworkConfig):
                key = f"config.{field.name}"
                if key in data:
                    kwargs[field.name] = data[key].item()
            config = NetworkConfig(**kwargs)
            return cls.from_weights(config, data["W"], data["Q"])

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
