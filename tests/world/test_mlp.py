"""The PPO networks in NumPy (mpc_hunt/world/mlp.py): their arithmetic, their files, the shipped ones, torch's."""

from __future__ import annotations

import io
import zipfile

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mpc_hunt.errors import DataFileError
from mpc_hunt.world.agent_view import ATTACKER_VIEW, DEFENDER_VIEW
from mpc_hunt.world.behaviours.ppo import ATTACKER_POLICY
from mpc_hunt.control.ppo_team import TEAM_POLICY, TEAM_VIEW
from mpc_hunt.world.mlp import MAX_WIDTH, load_mlp


def _arrays(inputs: int = 3, hidden: int = 4, side: str = "attacker", seed: int = 0) -> dict:
    rng = np.random.default_rng(seed)
    return {"side": np.array(side), "decision_steps": np.array(5), "clip": np.array(10.0), "epsilon": np.array(1e-8),
            "obs_mean": rng.normal(size=inputs), "obs_var": rng.uniform(0.5, 2.0, inputs),
            "w0": rng.normal(size=(hidden, inputs)), "b0": rng.normal(size=hidden),
            "w1": rng.normal(size=(2, hidden)), "b1": rng.normal(size=2)}


def _file(tmp_path, arrays: dict, name: str = "policy.npz"):
    path = tmp_path / name
    with open(path, "wb") as f:
        np.savez(f, **arrays)
    return path


def test_the_network_is_normalise_relu_linear_clip(tmp_path):
    a = _arrays()
    net = load_mlp(_file(tmp_path, a), "attacker", 3)
    view = np.array([0.3, -1.2, 2.0])
    x = np.clip((view - a["obs_mean"]) / np.sqrt(a["obs_var"] + 1e-8), -10, 10)
    expected = np.clip(a["w1"] @ np.maximum(a["w0"] @ x + a["b0"], 0) + a["b1"], -1, 1)
    assert np.allclose(net.action(view), expected, rtol=0, atol=1e-12)
    assert net.decision_steps == 5 and net.inputs == 3


def test_the_clip_of_the_normalised_view_and_of_the_action_bite(tmp_path):
    a = _arrays(inputs=1, hidden=1)
    a.update(obs_mean=np.zeros(1), obs_var=np.ones(1), clip=np.array(2.0), w0=np.ones((1, 1)), b0=np.zeros(1),
             w1=np.array([[0.1], [-0.1]]), b1=np.zeros(2))
    net = load_mlp(_file(tmp_path, a), "attacker", 1)
    assert np.allclose(net.action(np.array([100.0])), [0.2, -0.2])          # the view clipped at 2
    assert np.allclose(net.action(np.array([-5.0])), [0.0, 0.0])            # ReLU
    a.update(w1=np.array([[10.0], [-10.0]]))
    assert np.allclose(load_mlp(_file(tmp_path, a), "attacker", 1).action(np.array([1.0])), [1.0, -1.0])


BAD = {
    "another side's": lambda a: a.update(side=np.array("defender")),
    "a missing layer bias": lambda a: a.pop("b1"),
    "a layer of the wrong width": lambda a: a.update(w1=np.ones((2, 5))),
    "three outputs": lambda a: a.update(w1=np.ones((3, 4)), b1=np.ones(3)),
    "a NaN weight": lambda a: a["w0"].__setitem__((0, 0), np.nan),
    "a negative variance": lambda a: a["obs_var"].__setitem__(0, -1.0),
    "a statistic of the wrong length": lambda a: a.update(obs_mean=np.zeros(4)),
    "no decision steps": lambda a: a.pop("decision_steps"),
    "zero decision steps": lambda a: a.update(decision_steps=np.array(0)),
    "a text clip": lambda a: a.update(clip=np.array("ten")),
}


@pytest.mark.parametrize("damage", BAD, ids=list(BAD))
def test_a_damaged_policy_file_is_one_line_naming_it(tmp_path, damage):
    a = _arrays()
    BAD[damage](a)
    path = _file(tmp_path, a)
    with pytest.raises(DataFileError) as error:
        load_mlp(path, "attacker", 3)
    message = str(error.value)
    assert str(path) in message and "\n" not in message and "train_ppo.py" in message


def _npy() -> bytes:
    buffer = io.BytesIO()
    np.save(buffer, np.zeros(3))
    return buffer.getvalue()


def _zip_of_text() -> bytes:
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w") as z:
        z.writestr("side", "attacker")
    return buffer.getvalue()


@pytest.mark.parametrize("content", [b"", b"not a zip", b"PK\x03\x04broken", b'{"weights": []}',
                                     b"hello, these are not weights\n", _npy(), _zip_of_text()],
                         ids=["empty", "text", "broken-zip", "json", "text-line", "npy", "zip-of-text"])
def test_a_file_that_is_no_policy_is_one_whole_line(tmp_path, content):
    path = tmp_path / "policy.npz"
    path.write_bytes(content)
    with pytest.raises(DataFileError) as error:
        load_mlp(path, "attacker", 3)
    assert str(error.value) == (f"{path}: not a policy file (expected a NumPy .npz archive of a network's arrays); "
                                "write it again with python studies/train_ppo.py, or reinstall mpc-hunt")
    with pytest.raises(DataFileError, match="no such policy file"):
        load_mlp(tmp_path / "missing.npz", "attacker", 3)


def test_a_layer_wider_than_the_limit_is_refused_naming_it(tmp_path):
    with pytest.raises(DataFileError, match=f"layer 0: {MAX_WIDTH + 1} outputs, not 1 to {MAX_WIDTH} "):
        load_mlp(_file(tmp_path, _arrays(hidden=MAX_WIDTH + 1)), "attacker", 3)
    assert load_mlp(_file(tmp_path, _arrays(hidden=MAX_WIDTH)), "attacker", 3).inputs == 3


def test_a_pickled_array_is_refused_not_loaded(tmp_path):
    buffer = io.BytesIO()
    np.savez(buffer, side=np.array([{"evil": 1}], dtype=object))
    path = tmp_path / "pickle.npz"
    path.write_bytes(buffer.getvalue())
    with pytest.raises(DataFileError, match="not a policy file"):
        load_mlp(path, "attacker", 3)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-1e6, 1e6), min_size=ATTACKER_VIEW, max_size=ATTACKER_VIEW),
       st.lists(st.floats(-1e6, 1e6), min_size=TEAM_VIEW, max_size=TEAM_VIEW))
def test_the_shipped_networks_give_a_valid_action_for_any_view(attacker_view, defender_view):
    for net, view in ((ATTACKER_POLICY.network(), attacker_view), (TEAM_POLICY.network(), defender_view)):
        action = net.action(np.array(view))
        assert action.shape == (2,) and np.all(np.isfinite(action)) and np.all(np.abs(action) <= 1)


def test_numpy_evaluates_the_network_torch_trained():
    torch = pytest.importorskip("torch", reason="torch is the optional extra learn")
    pytest.importorskip("stable_baselines3", reason="Stable-Baselines3 is the optional extra learn")
    from gymnasium import spaces
    from stable_baselines3.common.policies import ActorCriticPolicy
    from stable_baselines3.common.running_mean_std import RunningMeanStd

    from studies.train_ppo import HIDDEN, export

    torch.manual_seed(0)
    policy = ActorCriticPolicy(spaces.Box(-1e3, 1e3, (DEFENDER_VIEW,)), spaces.Box(-1.0, 1.0, (2,)),
                               lambda _: 3e-4, net_arch={"pi": list(HIDDEN), "vf": list(HIDDEN)},
                               activation_fn=torch.nn.ReLU)
    for p in policy.parameters():                       # weights large enough that some actions clip
        p.data.normal_(0.0, 0.5)
    rng = np.random.default_rng(1)
    rms = RunningMeanStd(shape=(DEFENDER_VIEW,))
    rms.mean, rms.var = rng.normal(size=DEFENDER_VIEW), rng.uniform(0.1, 3.0, DEFENDER_VIEW)
    import tempfile
    from pathlib import Path
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "team.npz"
        export(policy, rms, 10.0, 1e-8, "team", path)
        net = load_mlp(path, "defender", DEFENDER_VIEW)
    views = rng.normal(scale=3.0, size=(200, DEFENDER_VIEW))
    normalised = np.clip((views - rms.mean) / np.sqrt(rms.var + 1e-8), -10, 10).astype(np.float32)
    expected, _ = policy.predict(normalised, deterministic=True)
    ours = np.array([net.action(v) for v in views])
    assert np.abs(ours - expected).max() < 1e-5            # float32 against float64
    assert np.any(np.abs(ours) == 1.0) and np.any(np.abs(ours) < 1.0)
