"""The controller spec: defaults defined once, checked once, its label the sweep's strategy, the same refusal of a
bad horizon from the command line, the sweep and the environments."""

from __future__ import annotations

import pickle
import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import small_scenario
from mpc_hunt.capture.problem import MAX_HORIZON, horizon_error
from mpc_hunt.cli.commands import _controller_spec, build_parser, main
from mpc_hunt.control.controllers import CONTROLLERS, SOLVING, controller_objective, keyword_options
from mpc_hunt.control.recommended import OTHER_HORIZON, PAPER, RECOMMENDED, RECOMMENDED_CONTROLLER
from mpc_hunt.control.spec import ControllerSpec, make_controller
from mpc_hunt.errors import OptionError, SettingError
from mpc_hunt.solving import registry
from mpc_hunt.world.belief import Belief

BASELINES = [c for c in CONTROLLERS if c not in SOLVING]


@st.composite
def specs(draw) -> tuple[ControllerSpec, dict]:
    """A valid spec and the fields it was given (the others left to their defaults)."""
    controller = draw(st.sampled_from(list(CONTROLLERS)))
    if controller not in SOLVING:
        return ControllerSpec(controller), {}
    given = {}
    if draw(st.booleans()):
        formulation, backend = draw(st.sampled_from(registry.pairs(objective=controller_objective(controller))))
        given |= {"formulation": formulation, "backend": backend}
    if draw(st.booleans()):
        given["horizon"] = draw(st.integers(1, MAX_HORIZON))
    return ControllerSpec(controller, **given), given


@settings(max_examples=150, deadline=None)
@given(specs())
def test_parse_of_the_label_is_the_spec_and_keeps_the_fields_given(drawn):
    spec, fields = drawn
    assert ControllerSpec.parse(spec.label) == spec and ControllerSpec.parse(spec.label).label == spec.label
    assert {k: getattr(spec, k) for k in fields} == fields
    if spec.controller in SOLVING:
        assert spec.label.split(":") == [spec.controller, spec.formulation, spec.backend, str(spec.horizon)]
    else:
        assert spec.label == spec.controller and spec.settings == {}


def test_unset_fields_take_the_defaults_defined_once():
    assert ControllerSpec().controller == RECOMMENDED_CONTROLLER
    for controller in SOLVING:
        assert ControllerSpec(controller).settings == RECOMMENDED
        assert ControllerSpec(controller, stage=PAPER).settings == PAPER
        assert ControllerSpec(controller, horizon=3).settings == RECOMMENDED | {"horizon": 3}
    other = ControllerSpec("paper", "qp")
    assert (other.backend, other.horizon) == (registry.formulation_class("qp").default_backend, OTHER_HORIZON)
    assert ControllerSpec.parse("paper:qp:daqp").settings == {"formulation": "qp", "backend": "daqp",
                                                               "horizon": OTHER_HORIZON}
    assert ControllerSpec.parse("enclose::daqp-condensed:4").settings == RECOMMENDED | {"backend": "daqp-condensed",
                                                                                      "horizon": 4}
    for controller in BASELINES:
        options = {"prediction": False} if "prediction" in keyword_options(controller) else {}
        spec = ControllerSpec(controller, options=options)
        assert (spec.formulation, spec.backend, spec.horizon) == (None, None, None)
        assert spec.settings == options


def test_a_numpy_horizon_is_kept_as_an_int():
    spec = ControllerSpec(horizon=np.int64(7))
    assert type(spec.horizon) is int and spec.label == f"{RECOMMENDED_CONTROLLER}:rti:hpipm:7"


@pytest.mark.parametrize("argv, flags", [
    (["--controller", "apf", "--time-limit", "0.5", "--score"], "--time-limit, --score"),
    (["--controller", "voronoi", "--horizon", "3"], "--horizon"),
    (["--formulation", "distributed", "--controller", "paper"], "--formulation"),
    (["--formulation", "qp", "--backend", "hpipm"], "--backend"),
])
def test_simulate_names_the_flags_of_the_refused_fields(capsys, argv, flags):
    err = _one_line_error(capsys, ["simulate", *argv])
    assert err.startswith(f"mpc-hunt simulate: error: {flags}: ")


def test_of_splits_make_controllers_keywords_into_fields_and_options():
    spec = ControllerSpec.of("enclose", {"horizon": 4, "time_limit": 0.5, "score": True})
    assert spec == ControllerSpec("enclose", horizon=4, options={"time_limit": 0.5, "score": True})
    assert spec.settings == RECOMMENDED | {"horizon": 4, "time_limit": 0.5, "score": True}
    assert ControllerSpec.of("voronoi", None) == ControllerSpec("voronoi")
    with pytest.raises(TypeError):
        spec.options["horizon"] = 5                         # a spec is frozen, its options too


BAD = {
    "controller": st.one_of(st.text().filter(lambda t: t not in CONTROLLERS), st.integers(), st.none()),
    "formulation": st.text(min_size=1).filter(lambda t: t not in registry.FORMULATIONS),
    "backend": st.one_of(st.text(min_size=1).filter(lambda t: t not in registry.BACKENDS),
                         st.sampled_from(["ipopt", "osqp"])),           # neither solves rti's stage form
    "horizon": st.one_of(st.integers(max_value=0), st.integers(min_value=MAX_HORIZON + 1), st.floats(),
                         st.booleans(), st.text()),
}


@settings(max_examples=200, deadline=None)
@given(st.sampled_from(sorted(BAD)).flatmap(lambda f: st.tuples(st.just(f), BAD[f])))
def test_every_invalid_field_is_refused_naming_it(bad):
    field, value = bad
    with pytest.raises(SettingError) as exc:
        ControllerSpec(**({"controller": "enclose", "formulation": "rti"} | {field: value}))
    assert exc.value.fields == (field,) and str(exc.value).startswith(f"{field}: ")
    if field == "horizon":
        assert exc.value.reason == horizon_error(value)


@pytest.mark.parametrize("make, fields, words", [
    (lambda: ControllerSpec("paper", "distributed"), ("formulation",),
     "distributed poses the enclose objective, not the paper objective of controller 'paper'"),
    (lambda: ControllerSpec("paper", "rti", "daqp-condensed"), ("backend",),
     "daqp-condensed solves only the enclose objective's QPs, not those of the paper objective of controller "
     "'paper': use another backend"),
    (lambda: ControllerSpec("apf", horizon=3, options={"time_limit": 1.0}), ("horizon", "time_limit"),
     "controller 'apf' solves no capture problem and takes only prediction: drop them"),
    (lambda: ControllerSpec("voronoi", options={"prediction": True, "score": True}), ("score",), "drop it"),
    (lambda: ControllerSpec.parse("voronoi:nlp"), ("formulation",), "solves no capture problem"),
    (lambda: ControllerSpec.parse("apf:"), ("formulation",), "solves no capture problem"),
    (lambda: ControllerSpec("enclose", options={"horizon": 3}), ("horizon",), "a field of the spec, not an option"),
    (lambda: ControllerSpec.of("enclose", ["horizon"]), ("options",), "a dict of the controller's options"),
    (lambda: ControllerSpec.parse("enclose:rti:hpipm:x"), ("horizon",), "expected a whole number from 1 to 200"),
])
def test_a_refusal_names_its_fields_and_how_to_fix_it(make, fields, words):
    with pytest.raises(SettingError) as exc:
        make()
    assert exc.value.fields == fields and words in exc.value.reason
    assert str(exc.value) == f"{', '.join(fields)}: {exc.value.reason}"
    copy = pickle.loads(pickle.dumps(exc.value))          # as a sweep's worker hands it back
    assert (copy.fields, copy.reason) == (exc.value.fields, exc.value.reason)


@pytest.mark.parametrize("objective", ["paper", "enclose"])
def test_which_objectives_a_pair_poses_is_the_registrys_one_check(objective):
    """The spec, compare's pairs and a solving controller refuse a pair exactly where
    :func:`~mpc_hunt.solving.registry.objective_refusal` does, naming the same field."""
    from mpc_hunt.bench.compare import check_pairs
    from mpc_hunt.control.strategy import HuntingStrategy
    from mpc_hunt.errors import BenchmarkError

    controller = next(c for c in SOLVING if controller_objective(c) == objective)
    posed = registry.pairs(objective=objective)
    for pair in registry.pairs():
        refusal = registry.objective_refusal(*pair, objective)
        assert (refusal is None) == (pair in posed)
        if refusal is None:
            assert ControllerSpec(controller, *pair).backend == pair[1] and check_pairs([":".join(pair)], objective)
            continue
        with pytest.raises(SettingError) as exc:
            ControllerSpec(controller, *pair)
        assert exc.value.fields == refusal.fields and exc.value.reason.startswith(refusal.reason)
        with pytest.raises(BenchmarkError, match=re.escape(refusal.reason)):
            check_pairs([":".join(pair)], objective)
        with pytest.raises(SettingError, match=re.escape(str(refusal))):
            HuntingStrategy(small_scenario(), CONTROLLERS[controller].reference, formulation=pair[0],
                            backend=pair[1], horizon=2)


@pytest.mark.parametrize("text", ["", ":rti", "a:b:c:d:e", "enclose:rti:hpipm:10:"])
def test_a_malformed_text_is_refused_with_the_form(text):
    with pytest.raises(OptionError, match=re.escape("expected controller[:formulation[:backend[:horizon]]]")):
        ControllerSpec.parse(text)


def test_build_is_make_controller_with_the_specs_settings():
    scenario = small_scenario()
    for spec in (ControllerSpec(), ControllerSpec("paper", "qp", "daqp", 3, options={"prediction": False}),
                 ControllerSpec("voronoi", options={"prediction": False}), ControllerSpec("trap", horizon=5)):
        built = spec.build(scenario, belief=Belief(eta=2.0))
        made = make_controller(spec.controller, scenario, belief=Belief(eta=2.0), **spec.settings)
        assert type(built) is type(made) and built.describe() == made.describe()
        if spec.controller in SOLVING:
            assert built.describe()["formulation"] == spec.formulation and built.horizon == spec.horizon


def _built_alike(made, built) -> None:
    """The two controllers are the same controller with the same settings: class, description, and a solving
    one's solver as set up (its backend's options, the evaluator's scoring, the tolerance)."""
    assert type(made) is type(built) and made.describe() == built.describe()
    if hasattr(made, "mpc"):
        mine, theirs = made.mpc.solver, built.mpc.solver
        assert vars(mine.backend) == vars(theirs.backend) and mine.score == theirs.score
        assert made.mpc.tolerance == built.mpc.tolerance


@pytest.mark.parametrize("name", sorted(CONTROLLERS))
def test_make_controller_builds_what_simulate_builds_for_every_registered_name(name):
    """``make_controller(name, s)`` and ``mpc-hunt simulate --controller name``: the same spec, the same
    controller; with settings, their flags' (``--horizon 3 --time-limit 0.5 --max-iter 7 --score``) too."""
    scenario = small_scenario()
    cli = _controller_spec(build_parser().parse_args(["simulate", "--controller", name]))
    assert ControllerSpec.of(name) == cli
    _built_alike(make_controller(name, scenario), cli.build(scenario))
    if name in SOLVING:
        flags = ["--horizon", "3", "--time-limit", "0.5", "--max-iter", "7", "--score", "--no-prediction"]
        settings = {"horizon": 3, "time_limit": 0.5, "max_iter": 7, "score": True, "prediction": False}
    else:
        taken = "prediction" in keyword_options(name)
        flags, settings = (["--no-prediction"], {"prediction": False}) if taken else ([], {})
    cli = _controller_spec(build_parser().parse_args(["simulate", "--controller", name, *flags]))
    assert ControllerSpec.of(name, settings) == cli
    _built_alike(make_controller(name, scenario, **settings), cli.build(scenario))


def _one_line_error(capsys, argv: list[str]) -> str:
    """``mpc-hunt argv``'s stderr: one line, exit status 2, no traceback."""
    try:
        code = main(argv)
    except SystemExit as exc:      # argparse's own errors exit
        code = exc.code
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err, err
    return err


@pytest.mark.parametrize("bad", [0, MAX_HORIZON + 1, 999])
def test_the_cli_the_sweep_and_the_environments_refuse_a_bad_horizon_alike(bad, capsys, tmp_path):
    """One message, after each boundary's own prefix naming the argument."""
    envs = pytest.importorskip("mpc_hunt.envs")
    messages = []
    err = _one_line_error(capsys, ["simulate", "--horizon", str(bad)])
    messages.append(re.fullmatch(r"mpc-hunt simulate: error: argument --horizon: (.*) \(see --help\)\n", err)[1])
    strategy = f"enclose:rti:hpipm:{bad}"
    err = _one_line_error(capsys, ["sweep", "--strategy", strategy, "--output", str(tmp_path / "s.db")])
    assert not (tmp_path / "s.db").exists()
    messages.append(re.fullmatch(rf"mpc-hunt sweep: error: --strategy '{strategy}': horizon: (.*)\n", err)[1])
    with pytest.raises(OptionError) as exc:
        envs.AttackerEnv(controller_options={"horizon": bad})
    messages.append(re.fullmatch(r"controller_options: horizon: (.*)", str(exc.value))[1])
    with pytest.raises(OptionError) as exc:
        envs.ControllerPolicy(envs.DefenderEnv(small_scenario()), "trap", {"horizon": bad})
    messages.append(re.fullmatch(r"options: horizon: (.*)", str(exc.value))[1])
    assert messages == [horizon_error(bad)] * 4


def test_an_environments_controller_is_a_name_or_a_spec():
    envs = pytest.importorskip("mpc_hunt.envs")
    spec = ControllerSpec("paper", "qp", "daqp", 2)
    assert envs.AttackerEnv(controller=spec).controller_spec is spec
    assert envs.AttackerEnv(controller="paper", controller_options={"formulation": "qp", "backend": "daqp",
                                                                    "horizon": 2}).controller_spec == spec
    assert envs.AttackerEnv().controller_spec == ControllerSpec()
    env = envs.AttackerEnv(scenario=small_scenario(), controller=ControllerSpec("voronoi"))
    env.reset(seed=0)
    assert env.controller.describe() == {"controller": "voronoi", "prediction": True}
