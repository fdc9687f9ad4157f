"""Bad input to the environments, as a new user tries it: one line in the toolkit's own words naming the argument
(an ``OptionError``, a ``ValueError``), refused before anything is built or changes; never NumPy's or Gymnasium's
error, never a silent wrong reading."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mpc_hunt.envs import AttackerEnv, DefenderEnv
from mpc_hunt.envs.learning import AttackerViewEnv, TeamHunts
from mpc_hunt.envs.parallel import ATTACKER, HuntParallelEnv
from mpc_hunt.errors import MpcHuntError, OptionError


def one_line(exc: pytest.ExceptionInfo, start: str, *words: str) -> str:
    """The refusal's message: one line, starting with ``start`` (the argument), holding each of ``words``."""
    message = str(exc.value)
    assert isinstance(exc.value, MpcHuntError) and "\n" not in message, message
    assert message.startswith(start) and all(w in message for w in words), message
    return message


# --- seeds -----------------------------------------------------------------------------------------------------

RESETS = {
    "HuntParallelEnv": lambda seed: HuntParallelEnv().reset(seed=seed),
    "AttackerEnv": lambda seed: AttackerEnv(controller="voronoi").reset(seed=seed),
    "DefenderEnv": lambda seed: DefenderEnv().reset(seed=seed),
    "AttackerViewEnv": lambda seed: AttackerViewEnv(controller="voronoi", teams=(3,)).reset(seed=seed),
    "TeamHunts": lambda seed: TeamHunts(1, ("gap",), seed=seed),
}
BAD_SEEDS = [
    pytest.param(-1, "must not be negative (a whole number from 0, or None), got -1", id="-1"),
    pytest.param(-(10**30), "must not be negative", id="-1e30"),
    pytest.param(np.int64(-5), "got -5", id="np.int64(-5)"),
    pytest.param(2.5, "a whole number from 0, or None, got float '2.5'", id="2.5"),
    pytest.param(True, "got bool 'True'", id="True"),
    pytest.param("7", "got str '7'", id="'7'"),
]


@pytest.mark.parametrize("bad, words", BAD_SEEDS)
@pytest.mark.parametrize("where", list(RESETS))
def test_a_bad_seed_is_refused_naming_it(where, bad, words):
    with pytest.raises(OptionError) as exc:
        RESETS[where](bad)
    one_line(exc, "seed: ", words)


@pytest.mark.parametrize("where", list(RESETS))
def test_a_good_seed_or_none_is_taken(where):
    for seed in (0, np.int64(3), 10**30, None):
        RESETS[where](seed)


PARALLEL = HuntParallelEnv()


@settings(max_examples=50, deadline=None)
@given(st.integers(max_value=-1))
def test_no_negative_seed_reaches_numpy(seed):
    with pytest.raises(OptionError) as exc:
        PARALLEL.reset(seed=seed)
    one_line(exc, "seed: ", "must not be negative")


# --- a step before the first reset -----------------------------------------------------------------------------

STEPS = {
    "HuntParallelEnv": lambda: HuntParallelEnv().step({ATTACKER: np.zeros(2)} | {f"defender_{i}": np.zeros(2)
                                                                                 for i in range(3)}),
    "AttackerEnv": lambda: AttackerEnv(controller="voronoi").step(np.zeros(2)),
    "DefenderEnv": lambda: DefenderEnv().step(np.zeros((3, 2))),
    "AttackerViewEnv": lambda: AttackerViewEnv(controller="voronoi").step(np.zeros(2)),
    "TeamHunts": lambda: TeamHunts(2, ("gap",)).step(np.zeros((6, 2))),
}


@pytest.mark.parametrize("where", list(STEPS))
def test_a_step_before_the_first_reset_is_one_line_saying_so(where):
    with pytest.raises(MpcHuntError) as exc:
        STEPS[where]()
    assert one_line(exc, "step: ") == "step: call reset() first"
