"""A trained policy network evaluated in NumPy: the multilayer perceptron of a PPO agent, without torch.

A policy file (``.npz``, written by ``python studies/train_ppo.py``) holds a policy's
observation normalisation (the running mean and variance the training kept, the clip) and
its layers: ``w0, b0, w1, b1, …``, each ``w`` of shape (outputs, inputs), ReLU between
them, the last layer the mean of the Gaussian policy, taken as the action (the
deterministic policy) and clipped to ±1. Beside them: ``side`` (``attacker`` or
``defender``), the view it reads (its length), and ``decision_steps``, the world's steps
each action is held for.

Every product is summed one input at a time, in a fixed order, and ReLU is exact: a
matrix product through BLAS, or a tanh through NumPy's SIMD, gives other last bits on
other CPUs (OpenBLAS and NumPy pick their kernels per CPU), and a closed loop amplifies
last bits into other hunts (docs/robustness.md).
"""

from __future__ import annotations

import zipfile
from dataclasses import dataclass
from functools import cache
from importlib import resources

import numpy as np

from mpc_hunt.compiled import kernel
from mpc_hunt.errors import DataFileError

SIDES = ("attacker", "defender")
MAX_LAYERS = 8
MAX_WIDTH = 4096
MAX_DECISION_STEPS = 1000


@dataclass(frozen=True)
class Mlp:
    """The network of a policy file (the module's docstring)."""

    side: str
    decision_steps: int
    mean: np.ndarray  # (inputs,): the observation's running mean
    scale: np.ndarray  # (inputs,): 1 / sqrt(variance + ε)
    clip: float
    weights: tuple[np.ndarray, ...]
    biases: tuple[np.ndarray, ...]

    @property
    def inputs(self) -> int:
        return len(self.mean)

    def action(self, view: np.ndarray) -> np.ndarray:
        """The policy's action for ``view`` (its length :attr:`inputs`): the mean of the last layer, in [−1, 1]."""
        x = np.clip((np.asarray(view, dtype=float) - self.mean) * self.scale, -self.clip, self.clip)
        last = len(self.weights) - 1
        for k, (w, b) in enumerate(zip(self.weights, self.biases)):
            x = layer(w, b, x, k != last)
        return np.clip(x, -1.0, 1.0)


@kernel
def layer(w: np.ndarray, b: np.ndarray, x: np.ndarray, relu: bool) -> np.ndarray:
    """b + w x, summed one input at a time in their order (the same bits on every CPU), then ReLU if ``relu`` (as
    NumPy's maximum: −0 and NaN kept)."""
    y = b.copy()
    for j in range(x.shape[0]):
        for i in range(y.shape[0]):
            y[i] += w[i, j] * x[j]
    if relu:
        for i in range(y.shape[0]):
            if not (y[i] >= 0.0 or y[i] != y[i]):
                y[i] = 0.0
    return y


@cache
def shipped_mlp(package: str, name: str, side: str, inputs: int) -> Mlp:
    """The policy file ``name`` shipped in ``package``, loaded once (:func:`load_mlp`)."""
    return load_mlp(resources.files(package).joinpath(name), side, inputs)


@dataclass(frozen=True)
class ShippedPolicy:
    """A policy shipped beside a module: its package, its file's name, the ``side`` it moves and the length of the
    view it reads."""

    package: str
    name: str
    side: str
    inputs: int

    def file(self):
        """The shipped policy file."""
        return resources.files(self.package).joinpath(self.name)

    def network(self, path=None) -> Mlp:
        """The shipped network (loaded once, :func:`shipped_mlp`), or the one in the policy file ``path``."""
        if path is None:
            return shipped_mlp(self.package, self.name, self.side, self.inputs)
        return load_mlp(path, self.side, self.inputs)


def load_mlp(path, side: str, inputs: int) -> Mlp:
    """The network in the policy file ``path`` for ``side``, reading views of ``inputs`` numbers; a damaged or
    foreign file is a one-line :class:`DataFileError` naming it."""
    fix = "write it again with python studies/train_ppo.py, or reinstall mpc-hunt"
    try:
        with open(path, "rb") as f:
            arrays = _archive(f) if zipfile.is_zipfile(f) else None  # NumPy would take it as an array or a pickle
    except FileNotFoundError:
        raise DataFileError(f"{path}: no such policy file; {fix}") from None
    except OSError as exc:
        raise DataFileError(f"{path}: cannot read ({exc.strerror or exc}); {fix}") from None
    except (ValueError, EOFError, zipfile.BadZipFile, KeyError) as exc:  # a damaged archive
        why = " ".join(str(exc).split()) or type(exc).__name__
        raise DataFileError(f"{path}: not a policy file ({why}); {fix}") from None
    if arrays is None or not all(isinstance(a, np.ndarray) for a in arrays.values()):  # members NumPy did not write
        raise DataFileError(f"{path}: not a policy file (expected a NumPy .npz archive of a network's arrays); {fix}")
    try:
        return _checked(arrays, side, inputs)
    except DataFileError as exc:
        raise DataFileError(f"{path}: {exc}; {fix}") from None


def _archive(f) -> dict:
    """The arrays of the .npz archive open as ``f``, none of them a pickle."""
    f.seek(0)
    with np.load(f, allow_pickle=False) as data:
        return {k: data[k] for k in data.files}


def _checked(arrays: dict, side: str, inputs: int) -> Mlp:
    def scalar(name: str, kind: str):
        value = arrays.get(name)
        if value is None or np.shape(value) != () or value.dtype.kind not in kind:
            raise DataFileError(f"'{name}' missing or not a single {'text' if kind == 'U' else 'number'}")
        return value.item()

    found = scalar("side", "U")
    if found != side:
        raise DataFileError(f"a policy of the {found!r} side, not the {side}'s")
    steps = scalar("decision_steps", "iu")
    if not 1 <= steps <= MAX_DECISION_STEPS:
        raise DataFileError(f"decision_steps {steps}, not 1 to {MAX_DECISION_STEPS}")
    clip = float(scalar("clip", "f"))
    if not 0 < clip < np.inf:
        raise DataFileError(f"clip {clip}, not a positive number")
    layers = sum(1 for k in arrays if k.startswith("w"))
    if not 1 <= layers <= MAX_LAYERS:
        raise DataFileError(f"{layers} layers, not 1 to {MAX_LAYERS}")
    weights, biases, width = [], [], inputs
    for k in range(layers):
        w, b = arrays.get(f"w{k}"), arrays.get(f"b{k}")
        if b is not None and b.ndim == 1 and not 1 <= len(b) <= MAX_WIDTH:
            raise DataFileError(f"layer {k}: {len(b)} outputs, not 1 to {MAX_WIDTH} (the limit of a layer's width)")
        if w is None or b is None or w.ndim != 2 or b.ndim != 1 or w.shape[1] != width or w.shape[0] != len(b):
            raise DataFileError(
                f"layer {k}: weights of shape (outputs, {width}) and biases of (outputs,) expected, "
                f"got {None if w is None else w.shape} and {None if b is None else b.shape}"
            )
        weights.append(np.asarray(w, dtype=float))
        biases.append(np.asarray(b, dtype=float))
        width = len(b)
    if width != 2:
        raise DataFileError(f"the last layer gives {width} numbers, not an action's 2")
    mean, var = arrays.get("obs_mean"), arrays.get("obs_var")
    if mean is None or var is None or np.shape(mean) != (inputs,) or np.shape(var) != (inputs,):
        raise DataFileError(f"obs_mean and obs_var: {inputs} numbers each expected (the {side}'s view)")
    mean, var = np.asarray(mean, dtype=float), np.asarray(var, dtype=float)
    everything = [mean, var, *weights, *biases]
    if not all(np.all(np.isfinite(a)) for a in everything) or np.any(var < 0):
        raise DataFileError("a NaN or infinite number, or a negative variance")
    epsilon = float(scalar("epsilon", "f"))
    if not 0 < epsilon < 1:
        raise DataFileError(f"epsilon {epsilon}, not in (0, 1)")
    return Mlp(side, int(steps), mean, 1.0 / np.sqrt(var + epsilon), clip, tuple(weights), tuple(biases))
