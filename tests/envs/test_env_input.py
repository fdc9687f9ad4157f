"""Bad input to the environments, as a new user tries it: one line in the toolkit's own words naming the argument
(an ``OptionError``, a ``ValueError``), refused before anything is built or changes; never NumPy's or Gymnasium's
error, never a silent wrong reading."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mpc_hunt.envs import AttackerEnv, DefenderEnv
from mpc_hunt.envs import learning
from mpc_hunt.envs.learning import MAX_TEAM_HUNTS, AttackerViewEnv, TeamHunts
from mpc_hunt.envs.parallel import ATTACKER, HuntParallelEnv
from mpc_hunt.errors import MpcHuntError, OptionError
from mpc_hunt.sweep.random_scenario import ScenarioRanges, random_scenario
from mpc_hunt.world.behaviours.base import sensed
from mpc_hunt.world.packed import sensing_radius


def one_line(exc: pytest.ExceptionInfo, start: str, *words: str) -> str:
    """The refusal's message: one line, starting with ``start`` (the argument), holding each of ``words``."""
    message = str(exc.value)
    assert isinstance(exc.value, MpcHuntError) and "\n" not in message, message
    assert message.startswith(start) and all(w in message for w in words), message
    return message


@pytest.fixture
def nothing_built(monkeypatch):
    """TeamHunts may build no hunt before its arguments are checked (10**7 of them would take hours)."""
    monkeypatch.setattr(learning, "DefenderEnv", lambda *a, **k: pytest.fail("a hunt was built"))


# --- TeamHunts' arguments --------------------------------------------------------------------------------------

@pytest.mark.parametrize("hunts, words", [
    (0, "must be at least 1, got 0"),
    (-1, "must be at least 1, got -1"),
    (2.5, f"a whole number from 1 to {MAX_TEAM_HUNTS}, got float 2.5"),
    (True, "got bool True"),                   # not 1
    ("3", "got str '3'"),
    (MAX_TEAM_HUNTS + 1, f"at most {MAX_TEAM_HUNTS} (docs/robustness.md, Limits), got {MAX_TEAM_HUNTS + 1}"),
    (10**7, f"at most {MAX_TEAM_HUNTS}"),
])
def test_team_hunts_refuse_a_bad_count_of_hunts_naming_it(nothing_built, hunts, words):
    with pytest.raises(OptionError) as exc:
        TeamHunts(hunts, ("gap",))
    one_line(exc, "hunts: ", words)


@settings(max_examples=50, deadline=None)
@given(st.one_of(st.integers(max_value=0), st.integers(min_value=MAX_TEAM_HUNTS + 1), st.floats(), st.booleans(),
                 st.none(), st.text(max_size=5)))
def test_team_hunts_take_no_count_outside_one_to_the_bound(hunts):
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(learning, "DefenderEnv", lambda *a, **k: pytest.fail("a hunt was built"))
        with pytest.raises(OptionError) as exc:
            TeamHunts(hunts, ("gap",))
    one_line(exc, "hunts: ")


@pytest.mark.parametrize("attackers, words", [
    ("gap", "got str 'gap'; for one, give ('gap',)"),                 # not 'g', 'a', 'p'
    ((), "empty; give at least one of the behaviour names (apf, flee, gap"),
    (["gap", "apf", "gap"], "gap more than once"),
    (("gapp",), "unknown behaviour 'gapp'"),
    (("gap", None), "unknown behaviour None"),
    (7, "got int '7'"),
])
def test_team_hunts_refuse_bad_attackers_naming_them(nothing_built, attackers, words):
    with pytest.raises(OptionError) as exc:
        TeamHunts(2, attackers)
    one_line(exc, "attackers: ", words)


def test_team_hunts_take_a_list_or_a_tuple_of_attackers():
    assert list(TeamHunts(2, ["gap", "apf"]).envs[1]) == list(TeamHunts(2, ("gap", "apf")).envs[1]) == ["gap", "apf"]
    assert len(TeamHunts(np.int64(2), ("gap",)).envs) == 2


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


# --- a hunt given to AttackerViewEnv's reset ---------------------------------------------------------------------

def _sensed_at_once(defenders: int):
    """A random hunt of ``defenders`` whose attacker senses one at its start: its first decision is its first step."""
    for seed in range(1000):
        s = random_scenario(np.random.default_rng(seed), ScenarioRanges(n_defenders=(defenders, defenders)), name="env")
        if len(sensed(np.array(s.attacker.start), s.defender_starts, sensing_radius(s))):
            return s
    raise AssertionError("no such hunt")


@pytest.mark.parametrize("teams", [(2, 3, 4, 5), (3,), (2, 4)])
@pytest.mark.parametrize("defenders", [2, 3, 6])
def test_a_given_hunt_is_played_with_its_own_team_at_every_seed(teams, defenders):
    """The agent's view and action are the same for any team, so a given hunt is played as it is: no team size is
    drawn for it (one not in ``teams`` too), whatever the seed."""
    scenario = _sensed_at_once(defenders)
    env = AttackerViewEnv(controller="voronoi", teams=teams)
    for seed in range(8):
        view, _ = env.reset(seed=seed, options={"scenario": scenario})
        assert env.env.scenario is scenario and env.env.hunts.team == defenders
        assert env.observation_space.contains(view)
        env.step(np.zeros(2))
    env.reset(seed=0)                                   # a random hunt again: one of teams' sizes
    assert env.env.hunts.team in teams


@pytest.mark.parametrize("bad", ["hunt", 3, [None]])
def test_a_given_hunt_that_is_no_scenario_is_one_line_at_every_seed(bad):
    env = AttackerViewEnv(controller="voronoi")
    for seed in range(4):
        with pytest.raises(OptionError) as exc:
            env.reset(seed=seed, options={"scenario": bad})
        one_line(exc, "options['scenario']: a Scenario")
