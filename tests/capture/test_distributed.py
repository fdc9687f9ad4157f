"""``distributed``: its control loop is its own path to the bit, one robot alone is ``rti``, the broadcast is the
attacker's model, the midpoint separation rows and the obstacle rows bind, and what it refuses."""

from __future__ import annotations

import time

import shutil
import warnings
import subprocess

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import mpc_hunt.formulations.team as team_module
from mpc_hunt.formulations.capture_model import parameter_vector, reference_size, stage_parameters, step_size, unpack
from mpc_hunt.formulations.distributed import DistributedFormulation
from mpc_hunt.formulations.team import NEIGHBOURS
from mpc_hunt.formulations.stage_model import SMOOTHING, stage_model
from mpc_hunt import (Attacker, CaptureProblem, CaptureSolver, Defender, HuntParameters, Obstacle, Scenario, Status,
                      shift_plan)
from mpc_hunt.bench.compare import check_pairs
from mpc_hunt.control.spec import ControllerSpec, make_controller
from mpc_hunt.capture.problem import Reference
from mpc_hunt.errors import MpcHuntError
from mpc_hunt.world.field import repulsion
from strategies import floats

ATTACKER = np.array([5.0, 11.0])
TOP = ATTACKER + [0.0, 0.6]                  # where two robots meet, 0.6 m north of the attacker
BELOW = ATTACKER + [0.0, -0.6]               # a third robot, out of their way
HORIZON = 5
D_MIN = HuntParameters().min_separation      # 0.2 m
GAUSS_SEIDEL = {"rounds": 2, "scheme": "gauss-seidel"}
OBSTACLE = ((5.6, 11.6), 0.2)                # its field reaches the attacker


def _scenario(defenders: int, obstacles=(), **hunt) -> Scenario:
    return Scenario(
        name="distributed",
        defenders=tuple(Defender(start=(float(i), 0.0), max_speed=0.08) for i in range(defenders)),   # r_d = 8 mm
        attacker=Attacker(start=(10.0, 10.0), nominal_velocity=(0.2, -0.2), max_speed=0.03, perception_radius=1.0),
        obstacles=tuple(Obstacle(centre=c, radius=r) for c, r in obstacles),
        hunt=HuntParameters(**hunt),
    )


def _problem(scenario, defenders, places, horizon=HORIZON, active=None, attacker=ATTACKER,
             attacker_place=None) -> CaptureProblem:
    """The enclose problem with every defender's place held over the horizon."""
    defenders = np.asarray(defenders, dtype=float)
    places = np.broadcast_to(np.asarray(places, dtype=float), (horizon,) + defenders.shape)
    target = np.broadcast_to(attacker if attacker_place is None else attacker_place, (horizon, 2))
    return CaptureProblem.at_state(scenario, attacker, defenders, horizon, active=active,
                                   reference=Reference(places, target, np.ones(horizon)))


def _on_circle(radius, degrees, centre=ATTACKER) -> np.ndarray:
    a = np.radians(np.asarray(degrees, dtype=float))
    return centre + radius * np.stack([np.cos(a), np.sin(a)], axis=1)


def _closed_loop(solver, scenario, defenders, places, steps):
    """(problem, solution) along a short hunt: the defenders go to each plan's first step, the attacker by its
    model, the next step starts from the plan shifted."""
    attacker, defenders, warm = ATTACKER.copy(), np.asarray(defenders, dtype=float), None
    for _ in range(steps):
        problem = _problem(scenario, defenders, places, attacker=attacker)
        solution = solver.solve(problem, warm)
        assert solution.success, solution.message
        yield problem, solution
        attacker = problem.attacker_step(attacker, defenders)
        defenders, warm = solution.plan[0], shift_plan(solution.plan)


def _gaps(solutions, i=0, j=1) -> np.ndarray:
    """|p_i − p_j| at every planned step of every solution."""
    return np.concatenate([np.linalg.norm(s.plan[:, i] - s.plan[:, j], axis=1) for s in solutions])


# --- 1. the loop path is the formulation's own path ---------------------------------------------------------------

TEAM = _on_circle(0.6, [0.0, 90.0, 180.0, 270.0])
TEAM_PLACES = _on_circle(0.5, [20.0, 110.0, 200.0, 290.0])


def _team_problems():
    """Four robots round the attacker, within its perception: on a ring, on a ring closer in, one of them held."""
    scenario = _scenario(4, (OBSTACLE,))
    yield _problem(scenario, TEAM, TEAM_PLACES)
    yield _problem(scenario, _on_circle(0.3, [10.0, 100.0, 190.0, 280.0]), TEAM_PLACES)
    yield _problem(scenario, TEAM, TEAM_PLACES, active=[True, False, True, True])


@pytest.mark.parametrize("backend", ["hpipm", "hpipm-codegen"])
@pytest.mark.parametrize("options", [{}, GAUSS_SEIDEL], ids=["jacobi", "gauss-seidel-2"])
def test_the_loop_gives_the_formulations_own_plans_to_the_bit(backend, options):
    """Cold, and along a closed loop warm-started from the shifted plan; the pushes on the attacker are not zero."""
    looped = CaptureSolver("distributed", backend, formulation_options=options)
    own = CaptureSolver("distributed", backend, loop=False, formulation_options=options)
    assert looped.on_steps and not own.on_steps
    for first in _team_problems():
        problem, warm = first, None
        for _ in range(3):
            a, b = looped.solve(problem, warm), own.solve(problem, warm)
            assert a.status is b.status is Status.OPTIMAL, (a.message, b.message)
            np.testing.assert_array_equal(a.plan, b.plan)
            assert a.iterations == b.iterations
            assert {k: a.extras[k] for k in ("qps", "rounds", "failed_robot_qps", "unseen_neighbours")} == \
                   {k: b.extras[k] for k in ("qps", "rounds", "failed_robot_qps", "unseen_neighbours")}
            assert a.extras["qps"] == problem.structure.planned * options.get("rounds", 1)
            assert np.abs(a.plan - problem.held_plan()).max() > 5e-3                       # the robots moved
            pushes = DistributedFormulation().team(problem).broadcast(a.x.reshape(HORIZON, -1, 2)).pushes
            assert np.abs(pushes).max() > 0.1
            warm = shift_plan(b.plan)
            problem = _problem(problem.scenario, b.plan[0], TEAM_PLACES, active=problem.controlled,
                               attacker=problem.attacker_step(problem.attacker_position, problem.defender_positions))


# --- 2. one robot alone is rti --------------------------------------------------------------------------------------

ROBOT = ATTACKER + [0.5, 0.2]               # within the attacker's perception: its push counts
FAR = np.array([[9.0, 11.0], [5.0, 15.0]])  # 3.5 m and more from everybody


@pytest.mark.parametrize("others", ["none", "held far", "planned far"])
def test_one_robot_alone_plans_as_rti(others):
    """With nobody else within perception or separation reach the robot's QP is rti's: the plans agree to 1e-12
    (measured: none 0, held far 7e-14); a team whose robots are all far apart makes rti's team QP, which the
    interior point solves by other iterates: to 1e-10 (measured 3.9e-12)."""
    place = ROBOT + [0.003, 0.004]           # within reach: the optimum lies inside the trust region
    if others == "none":
        problem = _problem(_scenario(1, (OBSTACLE,)), [ROBOT], [place], attacker_place=ATTACKER + [0.01, 0.0])
    else:
        defenders = np.vstack([ROBOT, FAR])
        problem = _problem(_scenario(3, (OBSTACLE,)), defenders, np.vstack([place, FAR + [0.003, -0.004]]),
                           attacker_place=ATTACKER + [0.01, 0.0],
                           active=[True, False, False] if others == "held far" else None)
    mine, theirs = CaptureSolver("distributed", "hpipm").solve(problem), CaptureSolver("rti", "hpipm").solve(problem)
    assert mine.status is theirs.status is Status.OPTIMAL
    assert np.abs(mine.plan[:, 0] - ROBOT).max() > 1e-3
    np.testing.assert_allclose(mine.plan, theirs.plan, rtol=0, atol=1e-10 if others == "planned far" else 1e-12)


# --- 3. the broadcast is the attacker's model -----------------------------------------------------------------------

offsets = st.tuples(floats(min_value=0.15, max_value=1.4), floats(min_value=-np.pi, max_value=np.pi))
steps = st.lists(floats(min_value=-1.0, max_value=1.0), min_size=4 * 4 * 2, max_size=4 * 4 * 2)
obstacle_centres = st.tuples(floats(min_value=4.0, max_value=6.0), floats(min_value=12.0, max_value=12.5))


def _rolled_out(theta, reference, structure, start) -> np.ndarray:
    """The robot's attacker positions at steps 1..N, its stage model fed its θ and reference as rti rolls its
    reference out: step 0 on the paper's field, the others on the smoothed one."""
    model, x, path = stage_model(structure), np.asarray(start, dtype=float), []
    for k, target in enumerate(reference.reshape(-1, 2)):
        stage = np.asarray(stage_parameters(theta, structure, k), dtype=float).ravel()
        if k == 0:
            stage[-1] = 0.0
        x = np.asarray(model.dynamics(x, target - x[2:], stage), dtype=float).ravel()
        path.append(x[:2])
    return np.array(path)


@settings(deadline=None, max_examples=40)
@given(st.lists(offsets, min_size=4, max_size=4), st.sampled_from([None, 0, 2]), steps, obstacle_centres)
def test_the_broadcast_is_the_attackers_model_and_each_robot_rolls_it_out(polar, held, moves, centre):
    """Under random plans of a team (one robot held or none): ā_1 is the world's attacker step (the paper's field),
    ā_k+1 the team's stage model's dynamics at (ā_k, D_k) (the smoothed field), each push k_d H(ā_k − p_j,k) (outside
    the band where H is smoothed) with its Jacobian (central differences), and every robot's roll-out of its own
    inputs gives ā. Measured over 300 random states: the paths agree to the bit, the pushes to 6e-16 relative;
    tolerances 1e-14 m, 1e-13 m and 1e-12."""
    defenders = ATTACKER + np.array([[r * np.cos(a), r * np.sin(a)] for r, a in polar])
    active = None if held is None else [i != held for i in range(4)]
    problem = _problem(_scenario(4, ((centre, 0.2),)), defenders, defenders, horizon=4, active=active)
    s, N = problem.structure, problem.horizon
    plans = (problem.x_from_plan(problem.held_plan()).reshape(N, -1, 2)
             + 0.008 * np.cumsum(np.reshape(moves[:N * s.planned * 2], (N, s.planned, 2)), axis=0))
    team = DistributedFormulation().team(problem)
    broadcast = team.broadcast(plans)
    path, pushes, jacobians = broadcast.path, broadcast.pushes, broadcast.jacobians
    positions = np.concatenate([problem.defender_positions[None], problem.plan_with(plans.reshape(-1))[:-1]])
    order = np.concatenate([np.flatnonzero(problem.controlled), np.flatnonzero(~problem.controlled)])
    np.testing.assert_array_equal(path[0], problem.attacker_position)
    np.testing.assert_allclose(path[1], problem.attacker_step(problem.attacker_position, positions[0]),
                               rtol=0, atol=1e-12)     # 2.2e-13 with four defenders 1e-12 m or less from R_agg
    model, theta = stage_model(s), np.append(parameter_vector(problem), SMOOTHING)
    for k in range(1, N - 1):
        x = np.concatenate([path[k], positions[k][problem.controlled].ravel()])
        step = np.asarray(model.dynamics(x, np.zeros(2 * s.planned), stage_parameters(theta, s, k))).ravel()
        np.testing.assert_allclose(path[k + 1], step[:2], rtol=0, atol=1e-14)
    hunt, radius = problem.scenario.hunt, problem.scenario.attacker.perception_radius
    for k in range(N):
        for slot, j in enumerate(order):
            def push(a):
                return hunt.k_d * repulsion((a - positions[k][j])[None], radius, hunt.eta)[0]
            h, off = 1e-6, abs(np.linalg.norm(path[k] - positions[k][j]) - radius)
            # Where H is rounded: step 0 takes w = 0, which formulations.field rounds within 1e-12 m of R_agg.
            rounded = 2 * SMOOTHING if k else 1e-9
            if off > rounded:
                np.testing.assert_allclose(pushes[k, slot], push(path[k]), rtol=1e-12, atol=1e-15)
            if off <= max(rounded, 2 * h):                          # central differences would straddle the kink
                continue
            numeric = np.column_stack([(push(path[k] + e) - push(path[k] - e)) / (2 * h) for e in h * np.eye(2)])
            np.testing.assert_allclose(jacobians[k, slot].reshape(2, 2, order="F"), numeric, rtol=1e-5, atol=1e-6)
    for i in range(s.planned):
        theta_i, reference, _ = team.robot_inputs(i, broadcast)
        np.testing.assert_array_equal(reference, plans[:, i].ravel())
        start = np.concatenate([problem.attacker_position, positions[0][order[i]]])
        rolled = _rolled_out(theta_i, reference, team.robot, start)
        np.testing.assert_allclose(rolled[:-1], path[1:], rtol=0, atol=1e-13)


# --- 4, 5. the separation rows --------------------------------------------------------------------------------------

PAIR = np.array([TOP - [0.115, 0.0], TOP + [0.115, 0.0], BELOW])          # the pair 0.23 m apart
PAIR_PLACES = np.array([TOP - [0.075, 0.0], TOP + [0.075, 0.0], BELOW])   # 0.15 m apart, 4 cm (5 steps) on
# Measured: the plans below keep d_min to 7e-16 (the rows' tangent half-planes hold it from inside, to HPIPM's
# tolerance); 1e-9 leaves a margin for HPIPM's stopping point.
SEPARATION_TOL = 1e-9


@pytest.mark.parametrize("options", [{}, GAUSS_SEIDEL], ids=["jacobi", "gauss-seidel-2"])
def test_two_robots_whose_places_are_closer_than_d_min_keep_it_and_the_rows_bind(options):
    """Along six closed-loop steps every planned step keeps d_min, and it binds (Gauss–Seidel's rounds close in on it
    from above: 5e-7 by the fourth step)."""
    solver = CaptureSolver("distributed", "hpipm", formulation_options=options)
    gaps = _gaps(s for _, s in _closed_loop(solver, _scenario(3), PAIR, PAIR_PLACES, steps=6))
    assert gaps.min() >= D_MIN - SEPARATION_TOL
    assert gaps.min() <= D_MIN + 1e-6


def test_without_the_separation_the_same_places_bring_the_robots_closer():
    """With d_min = 0 the same problem's plans come 5 cm inside 0.2 m: the rows are what keeps it."""
    solver = CaptureSolver("distributed", "hpipm")
    gaps = _gaps(s for _, s in _closed_loop(solver, _scenario(3, min_separation=0.0), PAIR, PAIR_PLACES, steps=6))
    assert gaps.min() < D_MIN - 0.04


def _rows_to_the_reference(monkeypatch):
    """The rows each robot would keep to its team-mates' reference positions, d_min from them (not d_min / 2 from
    the midpoints): its θ's slots moved from the midpoint to the team-mate's reference, its d_min doubled."""
    midpoint_inputs = team_module.Team.robot_inputs

    def robot_inputs(team, i, broadcast):
        theta, reference, unseen = midpoint_inputs(team, i, broadcast)
        robot, N = team.robot, team.robot.horizon
        parts = unpack(theta, robot)                                   # views into θ
        offset = reference_size(1)
        slots = parts["reference"].reshape(N, step_size(robot))[:, offset:offset + 2 * robot.fixed]
        slots[:] = 2 * slots - np.tile(reference.reshape(N, 2), robot.fixed)
        parts["min_separation"][:] *= 2
        return theta, reference, unseen

    monkeypatch.setattr(team_module.Team, "robot_inputs", robot_inputs)


def test_in_one_jacobi_round_two_robots_heading_for_each_others_place_keep_d_min(monkeypatch):
    """Both move towards each other in the same round, each against its row to the midpoint of their references:
    they stop d_min apart. Rows to the other's reference position let each come d_min from where the other was,
    1.2 cm inside d_min."""
    scenario = _scenario(3)
    start = np.array([TOP - [0.11, 0.0], TOP + [0.11, 0.0], BELOW])      # 0.22 m apart
    problem = _problem(scenario, start, start[[1, 0, 2]])
    solution = CaptureSolver("distributed", "hpipm").solve(problem)
    assert solution.status is Status.OPTIMAL
    moved = (solution.plan[:, :2, 0] - start[:2, 0]) * [1, -1]               # towards each other
    assert moved[-1].min() > 5e-3
    gaps = _gaps([solution])
    assert gaps.min() >= D_MIN - SEPARATION_TOL and gaps.min() <= D_MIN + 1e-6
    _rows_to_the_reference(monkeypatch)
    assert _gaps([CaptureSolver("distributed", "hpipm").solve(problem)]).min() < D_MIN - 0.01


@pytest.mark.parametrize("options", [{}, GAUSS_SEIDEL], ids=["jacobi", "gauss-seidel-2"])
def test_a_robot_does_not_hold_a_spot_its_team_mate_plans_into(options):
    """Two robots d_min apart driving east in file, their last plans the reference; the leader's place is where it
    stands. Held where it stands it would break its row to their midpoint, which has moved east with the plans,
    so its row is relaxed only to what its reference keeps (none here): it moves on, and the follower behind it
    keeps d_min. (Relaxed to the held plan's values, as rti's team rows are, the pair came 1.6 cm inside d_min,
    2.4 cm with Gauss–Seidel's rounds.)"""
    start = np.array([TOP - [0.1, 0.0], TOP + [0.1, 0.0]])
    warm = start[None] + 0.007 * np.arange(1, HORIZON + 1)[:, None, None] * [1.0, 0.0]
    problem = _problem(_scenario(2), start, [TOP + [0.3, 0.0], start[1]])
    solution = CaptureSolver("distributed", "hpipm", formulation_options=options).solve(problem, warm)
    assert solution.status is Status.OPTIMAL
    assert _gaps([solution]).min() >= D_MIN - SEPARATION_TOL
    assert solution.plan[0, 1, 0] > start[1, 0] + 5e-3                    # the leader moved on


# --- 6. the obstacle rows -------------------------------------------------------------------------------------------

NEAR = (tuple(TOP + [0.3, 0.0]), 0.1)        # its safety circle (R + R_safe = 0.2 m) 2 cm east of robot 0
OBSTACLE_TOL = 1e-9   # measured: the plans keep R + R_safe to 3e-16 (as SEPARATION_TOL)


def _near_obstacle(**hunt):
    defenders = np.array([TOP + [0.08, 0.0], BELOW, ATTACKER - [0.6, 0.0]])
    places = defenders.copy()
    places[0] = TOP + [0.15, 0.0]                                # 5 cm inside the safety circle
    return _scenario(3, (NEAR,), **hunt), defenders, places


def _obstacle_gaps(solutions) -> np.ndarray:
    centre, radius = NEAR
    return np.concatenate([np.linalg.norm(s.plan[:, 0] - centre, axis=1) for s in solutions]) - radius


@pytest.mark.parametrize("options", [{}, GAUSS_SEIDEL], ids=["jacobi", "gauss-seidel-2"])
def test_a_robot_whose_place_is_inside_an_obstacles_safety_circle_stops_on_it(options):
    """Along six closed-loop steps robot 0 keeps R_safe from the obstacle, on its boundary by the second step; with
    R_safe = 0 the same place takes it 5 cm inside."""
    solver = CaptureSolver("distributed", "hpipm", formulation_options=options)
    scenario, defenders, places = _near_obstacle()
    gaps = _obstacle_gaps(s for _, s in _closed_loop(solver, scenario, defenders, places, steps=6))
    safety = scenario.hunt.safety_distance
    assert gaps.min() >= safety - OBSTACLE_TOL
    assert gaps.min() <= safety + 1e-6
    scenario, defenders, places = _near_obstacle(safety_distance=0.0)
    solver = CaptureSolver("distributed", "hpipm", formulation_options=options)
    relaxed = _obstacle_gaps(s for _, s in _closed_loop(solver, scenario, defenders, places, steps=6))
    assert relaxed.min() < safety - 0.04


# --- 7, 8. what it refuses ------------------------------------------------------------------------------------------

def test_the_paper_objective_is_refused_everywhere():
    """A solve returns ERROR naming the objective; the loop, and a benchmark's pair, raise; the benchmark's pairs
    for an objective hold distributed only for enclose."""
    paper = CaptureProblem.at_state(_scenario(4), ATTACKER, TEAM, HORIZON)
    assert paper.objective == "paper"
    solution = CaptureSolver("distributed").solve(paper)
    assert solution.status is Status.ERROR and "not the paper objective" in solution.message \
        and "enclose" in solution.message
    with pytest.raises(MpcHuntError, match="objective: .*not the paper objective"):
        CaptureSolver("distributed").step_for(paper)
    with pytest.raises(MpcHuntError, match="distributed poses the enclose objective, not the paper objective"):
        check_pairs(["distributed"], "paper")
    with pytest.raises(MpcHuntError, match="distributed poses the enclose objective, not the paper objective"):
        check_pairs(["distributed:hpipm"], "paper")
    assert not [p for p in check_pairs(None, "paper") if p[0] == "distributed"]
    assert ("distributed", "hpipm") in check_pairs(None, "enclose")
    assert check_pairs(["distributed:hpipm"], "enclose") == [("distributed", "hpipm")]
    # a controller posing the paper's objective, and a sweep's strategy for it, are refused before any hunt
    with pytest.raises(MpcHuntError, match="distributed poses the enclose objective, not the paper objective of "
                                           "controller 'paper'"):
        make_controller("paper", _scenario(4), formulation="distributed")
    with pytest.raises(MpcHuntError, match="not the paper objective of controller 'paper'"):
        ControllerSpec.parse("paper:distributed:hpipm:5")
    for controller in ("enclose", "contain", "adapt"):
        assert ControllerSpec.parse(f"{controller}:distributed:hpipm:5").formulation == "distributed"
        assert make_controller(controller, _scenario(4), formulation="distributed").mpc.solver.formulation.per_robot


@pytest.mark.parametrize("options, name", [({"rounds": 0}, "rounds"), ({"rounds": 1.5}, "rounds"),
                                           ({"rounds": True}, "rounds"), ({"scheme": "x"}, "scheme"),
                                           ({"bogus": 1}, "bogus")])
def test_a_bad_option_is_an_error_that_names_it(options, name):
    with pytest.raises(MpcHuntError, match=f"formulation_options: .*{name}"):
        CaptureSolver("distributed", "hpipm", formulation_options=options)


# --- 9. the C export ------------------------------------------------------------------------------------------------

@pytest.mark.skipif(shutil.which("make") is None or shutil.which("gcc") is None, reason="needs make and gcc")
def test_a_robots_exported_step_prints_its_plan_of_the_teams_first_round(tmp_path):
    """Robot 1's step of the team's first Jacobi round, as C: the program prints Python's plan (to 1e-9, as the
    other exports), which is robot 1's part of the team's plan."""
    problem = next(_team_problems())
    solver = CaptureSolver("distributed", "hpipm-codegen")
    folder = tmp_path / "robot1"
    files = solver.export(folder, problem, robot=1)
    assert {f.name for f in files} >= {"capture_step.c", "mpc_hunt_step.h", "input.txt", "expected.txt", "Makefile"}
    expected = np.loadtxt(folder / "expected.txt")
    team = solver.solve(problem)
    np.testing.assert_array_equal(expected, team.plan[:, 1].ravel())
    assert f"#define MPC_HUNT_PLAN {2 * HORIZON}" in (folder / "mpc_hunt_step.h").read_text()
    subprocess.run(["make", "-s", "-C", str(folder), "CFLAGS=-O1"], check=True, capture_output=True, timeout=300)
    with open(folder / "input.txt") as stdin:
        run = subprocess.run([str(folder / "capture_step")], stdin=stdin, capture_output=True, text=True,
                             timeout=60)
    assert run.returncode == 0, run.stderr
    plan = np.array(run.stdout.split(), dtype=float)
    assert plan.shape == expected.shape
    np.testing.assert_allclose(plan, expected, rtol=0, atol=1e-9)
    for robot in (-1, 4):
        with pytest.raises(MpcHuntError, match=f"robot: 4 defenders are planned \\(index 0 to 3\\), not {robot}"):
            solver.export(tmp_path / "bad", problem, robot=robot)


# --- 10. neighbours beyond the slots --------------------------------------------------------------------------------

@pytest.mark.parametrize("robots, radius, unseen", [(NEIGHBOURS + 2, 0.12, 1), (NEIGHBOURS + 1, 0.12, 0),
                                                    (NEIGHBOURS + 2, 0.9, 0)])
def test_team_mates_within_reach_beyond_the_slots_are_counted(robots, radius, unseen):
    """Packed on a circle of radius 0.12 m every robot has all the others within reach (d_min + 2ρ = 0.245 m):
    one too many for the slots with NEIGHBOURS + 2 robots, none with NEIGHBOURS + 1; spread 0.9 m out, none."""
    defenders = _on_circle(radius, np.arange(robots) * 360.0 / robots)
    problem = _problem(_scenario(robots), defenders, defenders, horizon=2)
    solution = CaptureSolver("distributed", "hpipm", score=False).solve(problem)
    assert solution.status.usable, solution.message
    assert solution.extras["unseen_neighbours"] == unseen


# --- 11. a robot's step condensed, on DAQP (the default backend) ----------------------------------------------------

def _plans_along(solver, problem, steps=3):
    """The plans of ``steps`` steps of ``solver`` along its own closed loop from ``problem``."""
    plans, warm = [], None
    for _ in range(steps):
        solution = solver.solve(problem, warm)
        assert solution.status.usable, solution.message
        plans.append(solution.plan)
        warm = shift_plan(solution.plan)
    return plans


def test_the_default_backend_condenses_and_gives_hpipms_plans():
    """The condensed QP on DAQP has the stage QP's optimum: HPIPM's plans within HPIPM's tolerance (measured:
    2.4e-10 m), on loops and on the formulation's own path, Jacobi and Gauss–Seidel."""
    assert CaptureSolver("distributed").backend.name == "daqp-condensed"
    for options in ({}, GAUSS_SEIDEL):
        for problem in _team_problems():
            reference = _plans_along(CaptureSolver("distributed", "hpipm", formulation_options=options), problem)
            for loop in (True, False):
                solver = CaptureSolver("distributed", loop=loop, formulation_options=options)
                for a, b in zip(_plans_along(solver, problem), reference):
                    np.testing.assert_allclose(a, b, rtol=0, atol=1e-8)


def test_each_robot_starts_from_its_own_last_active_set():
    """The same inputs again: warm, DAQP starts from the working set it ended with and stops at once (an
    iteration, the plan within 1e-12 m (measured: 1.8e-15); a loop of its own (another robot's buffer) starts
    cold, as the first did (21 iterations)."""
    problem = next(_team_problems())
    team = CaptureSolver("distributed").step_for(problem)
    team.load(problem)
    robot = team.robot(0)
    theta, reference = robot.theta.copy(), robot.reference.copy()
    assert robot.step().usable
    cold, plan = robot.iterations, robot.plan.copy()
    assert cold > 2                                   # rows bind: a cold start adds them one by one
    robot.theta[:], robot.reference[:] = theta, reference
    assert robot.step().usable and robot.iterations == 1
    np.testing.assert_allclose(robot.plan, plan, rtol=0, atol=1e-12)
    other = team.robots[1]
    other.theta[:], other.reference[:] = theta, reference
    assert other.step().usable and other.iterations == cold


def test_without_a_compiler_the_same_step_runs_interpreted(monkeypatch, tmp_path):
    """No compiler: one warning, CasADi's condensing and DAQP's Python package, the compiled step's plans (within
    1e-12 m; measured: 1.8e-15)."""
    from mpc_hunt.solving.compiled import CompilationWarning

    problem = next(_team_problems())
    compiled = _plans_along(CaptureSolver("distributed"), problem)
    monkeypatch.setenv("CC", str(tmp_path / "no-such-compiler"))
    with pytest.warns(CompilationWarning, match="interpreted"):
        interpreted = _plans_along(CaptureSolver("distributed"), problem)
    for a, b in zip(interpreted, compiled):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)


@pytest.mark.parametrize("interpreted", [False, True], ids=["compiled", "interpreted"])
def test_a_non_finite_input_fails_the_step_and_keeps_the_reference(monkeypatch, tmp_path, interpreted):
    if interpreted:
        monkeypatch.setenv("CC", str(tmp_path / "no-such-compiler"))
    problem = next(_team_problems())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        team = CaptureSolver("distributed").step_for(problem)
    team.load(problem)
    robot = team.robot(2)
    robot.theta[0] = np.nan
    status = robot.step()
    assert not status.usable and "non-finite input" in robot.message
    np.testing.assert_array_equal(robot.plan, robot.reference)


def test_the_papers_objective_is_not_the_condensed_backends():
    """Eq. 14's slacks enter linearly: the condensed Hessian is singular, so the backend takes enclose only."""
    from mpc_hunt.solving.registry import pairs

    problem = CaptureProblem.at_state(_scenario(3), ATTACKER, TEAM[:3], HORIZON)
    assert problem.objective == "paper"
    solution = CaptureSolver("rti", "daqp-condensed").solve(problem)
    assert solution.status is Status.ERROR and "backend daqp-condensed solves only the enclose objective" in \
        solution.message
    assert ("rti", "daqp-condensed") not in pairs(objective="paper")
    assert ("rti", "daqp-condensed") in pairs(objective="enclose")
    assert ("rti", "daqp-condensed") not in check_pairs(["rti"], "paper")        # a formulation alone: its pairs
    assert ("rti", "daqp-condensed") in check_pairs(["rti"], "enclose")          # that pose the objective


def test_two_solvers_share_a_structures_library_each_warm_starting_from_its_own_solves():
    """A structure's condensing and C library are built once a process (a sweep's every hunt has its own solver);
    each step keeps its own DAQP workspace, so one solver's warm start never reaches another's."""
    problem = next(_team_problems())
    first, second = (CaptureSolver("distributed").step_for(problem) for _ in range(2))
    assert first.robot(0).step_function.library is second.robot(0).step_function.library is not None
    first.load(problem)
    second.load(problem)
    assert first.robot(0).step().usable
    cold = first.robot(0).iterations
    assert first.robot(0).step().usable and first.robot(0).iterations == 1       # warm from its own last solve
    assert second.robot(0).step().usable and second.robot(0).iterations == cold  # cold: nothing of the first's


def test_a_distributed_step_times_every_robots_evaluations():
    problem = next(_team_problems())
    team = CaptureSolver("distributed").step_for(problem)
    for robot in team.robots:
        evaluate = robot._evaluate
        robot._evaluate = lambda evaluate=evaluate: (time.sleep(0.05), evaluate())    # each 50 ms longer
    team.load(problem)
    assert team.step().usable
    assert team.qps >= len(team.robots) and team.qps * 0.05 <= team.evaluation_time <= sum(team.robot_times)
    team.load(problem)                                  # afresh (a sleep's overrun on a busy machine: within 50 ms)
    assert team.step().usable and team.qps * 0.05 <= team.evaluation_time < (team.qps + 1) * 0.05
