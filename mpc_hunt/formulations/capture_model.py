"""The capture-stage model in CasADi: one symbolic source for every formulation.

Built once per structure (controlled defenders, held defenders, obstacles,
horizon) with the state and the scenario's numbers as parameters θ, so a solve
at a new state only changes numbers. The NumPy evaluator
(:mod:`mpc_hunt.capture.evaluator`) is an independent implementation of the same maths.
"""

from __future__ import annotations

from functools import cached_property, lru_cache

import casadi as ca
import numpy as np

from mpc_hunt.capture.problem import CaptureProblem
from mpc_hunt.capture.structure import Structure
from mpc_hunt.formulations.field import norm, obstacle_repulsion, repulsion, saturate

SCALARS = (
    "perception_radius",
    "eta",
    "k_d",
    "k_o",
    "attacker_max_speed",
    "protective_distance",
    "safety_distance",
    "min_separation",
    "min_attacker_distance",
    "ring_radius",
    "time_step",
    "hunt_radius",
    "w_force",
    "w_ring",
    "w_move",
    "w_equal",
)


ENCLOSE_SCALARS = ("w_attacker", "w_edge", "edge_margin")
FAR = 1e9  # m: the arena's edges when a scenario has none (no edge term, no bound)


def reference_size(nc: int) -> int:
    """One step's reference: the controlled defenders' places, the attacker's, the places' weight."""
    return 2 * nc + 3


# A robot's step (``Structure.robot``) adds, after its reference: its neighbour slots (the midpoints between it and
# its nearest team-mates at step k), the rest of the team's push on the attacker at the team's predicted attacker
# position ā_k, that push's Jacobian in the attacker's position (2×2, column by column), and ā_k itself.
TEAM_STEP = ("pushed", 2), ("push_jacobian", 4), ("push_attacker", 2)


def step_size(structure: Structure) -> int:
    """Numbers in one step of the reference part of θ (:func:`reference_size`, and a robot's team terms)."""
    size = reference_size(structure.planned)
    return size + 2 * structure.fixed + sum(n for _, n in TEAM_STEP) if structure.robot else size


def _layout(structure: Structure, steps: int | None = None) -> list[tuple[str, int]]:
    """θ's parts; ``enclose`` adds the arena, its weights and ``steps`` steps of the reference (by default the
    structure's :attr:`~mpc_hunt.capture.structure.Structure.reference_steps`). A robot's θ holds no held
    defenders (its neighbours move, step by step), and adds the team's mean step (``length``, the objective's
    scale) and the rest of the team's push on the attacker now (``pushed``)."""
    nc, nf, m = structure.planned, structure.fixed, structure.obstacles
    steps = structure.reference_steps if steps is None else steps
    layout = [
        ("attacker", 2),
        ("controlled", 2 * nc),
        ("held", 0 if structure.robot else 2 * nf),
        ("desired", 2),
        ("nominal", 2),
        ("centres", 2 * m),
        ("radii", m),
        ("step_limits", nc),
    ] + [(s, 1) for s in SCALARS]
    if structure.objective == "enclose":
        layout += [("arena", 4)] + [(s, 1) for s in ENCLOSE_SCALARS]
        if structure.robot:
            layout += [("length", 1), ("pushed", 2)]
        layout += [("reference", steps * step_size(structure))]
    return layout


def unpack(theta, structure: Structure, steps: int | None = None) -> dict:
    """The named parts of θ (symbols or numbers), in the order of :func:`_layout`."""
    out, offset = {}, 0
    for name, size in _layout(structure, steps):
        out[name] = theta[offset : offset + size]
        offset += size
    return out


def parameter_size(structure: Structure, steps: int | None = None) -> int:
    return sum(size for _, size in _layout(structure, steps))


def step_reference(p: dict, k: int, structure: Structure):
    """Step k's reference (k = 0..steps−1) from unpacked θ: (places (nc·2), attacker (2), weight)."""
    nc = structure.planned
    ref = p["reference"][k * step_size(structure) :]
    return ref[: 2 * nc], ref[2 * nc : 2 * nc + 2], ref[2 * nc + 2]


def team_step(p: dict, structure: Structure) -> dict:
    """A robot's team terms of its stage (θ of one stage, :data:`TEAM_STEP`): ``slots`` (K·2), ``pushed`` (2),
    ``push_jacobian`` (2×2), ``push_attacker`` (2)."""
    offset = reference_size(structure.planned)
    out = {"slots": p["reference"][offset : offset + 2 * structure.fixed]}
    offset += 2 * structure.fixed
    for name, size in TEAM_STEP:
        out[name] = p["reference"][offset : offset + size]
        offset += size
    out["push_jacobian"] = ca.reshape(out["push_jacobian"], 2, 2)
    return out


def stage_parameters(theta, structure: Structure, k: int):
    """The θ of one stage (its own step of the reference) from the whole horizon's θ, for stage k = 0..N.

    For ``paper`` every stage shares θ. Stage 0 has no reference of its own (its residuals are not part of the
    objective) and takes stage 1's; a robot's stage 0 takes the push on the attacker where it stands now
    (``pushed``: the attacker's first move follows from the state alone). The last entry (the smoothing width)
    is kept.
    """
    if structure.objective == "paper":
        return theta
    common = parameter_size(structure, 0)
    size = step_size(structure)
    step = theta[common + (max(k, 1) - 1) * size : common + max(k, 1) * size]
    if k == 0 and structure.robot:
        p = unpack(theta, structure)
        step = ca.vertcat(step[: size - 8], p["pushed"], ca.DM.zeros(4), p["attacker"])
    return ca.vertcat(theta[:common], step, theta[-1])


def parameter_vector(problem: CaptureProblem) -> np.ndarray:
    """θ for ``problem``, in the order of :func:`_layout`."""
    theta = np.empty(parameter_size(problem.structure))
    parameter_writer(problem.structure).write(problem, theta)
    return theta


class ParameterWriter:
    """θ of one (team) structure's problems, written into an array in place part by part (:func:`_layout`).

    What a problem's scenario alone fixes (the attacker's nominal velocity, the obstacles, the hunt's numbers,
    each defender's step limit, the arena) is worked out once per scenario and copied in; a control step writes
    only numbers, with no array of θ's size built. A robot's θ (``Structure.robot``) is its team's to write
    (:mod:`mpc_hunt.formulations.team`).
    """

    def __init__(self, structure: Structure):
        if structure.robot:
            raise ValueError("a robot's parameters are written by its team (mpc_hunt.formulations.team)")
        self.structure = structure
        self.size = parameter_size(structure)
        at, offset = {}, 0
        for name, size in _layout(structure):
            at[name] = slice(offset, offset + size)
            offset += size
        self._at = at
        # Runs of θ written at once: the nominal velocity and the obstacles; the scenario's scalars (SCALARS up to
        # the weights); the arena and the enclose weights.
        self._scenario_run = slice(at["nominal"].start, at["radii"].stop)
        self._scalars = slice(at[SCALARS[0]].start, at["hunt_radius"].stop)
        self._weights = slice(at["w_force"].start, at["w_equal"].stop)
        self._enclose = slice(at["arena"].start, at[ENCLOSE_SCALARS[-1]].stop) if "arena" in at else None
        self._fixed: tuple = (None, ())  # (a scenario, its numbers): read and replaced whole

    def _scenario_numbers(self, problem: CaptureProblem) -> tuple:
        """(nominal velocity and obstacles, the scenario's scalars, every defender's step limit, the arena)."""
        s = problem.scenario
        scenario, numbers = self._fixed
        if s is not scenario:  # a scenario is frozen: its numbers are too
            hunt = s.hunt
            run = np.concatenate(
                [
                    np.ravel(np.asarray(v, dtype=float))
                    for v in (problem.nominal_velocity, s.obstacle_centres, s.obstacle_radii)
                ]
            )
            scalars = np.array(
                [
                    s.attacker.perception_radius,
                    hunt.eta,
                    hunt.k_d,
                    hunt.k_o,
                    s.attacker.max_speed,
                    hunt.protective_distance,
                    hunt.safety_distance,
                    hunt.min_separation,
                    hunt.min_attacker_distance,
                    problem.ring_radius,
                    hunt.time_step,
                    hunt.hunt_radius,
                ],
                dtype=float,
            )
            arena = s.arena if s.arena is not None else (-FAR, -FAR, FAR, FAR)
            numbers = (run, scalars, np.asarray(problem.step_limits, dtype=float), tuple(arena))
            self._fixed = (s, numbers)
        return numbers

    def write(self, problem: CaptureProblem, theta: np.ndarray) -> None:
        """``problem``'s θ (of this structure) into ``theta[:size]``, a contiguous float array's."""
        if not theta.flags.c_contiguous:
            raise ValueError("θ is written into a contiguous array")
        at, structure = self._at, self.structure
        run, scalars, step_limits, arena = self._scenario_numbers(problem)
        c, p_d = problem.controlled, problem.defender_positions
        theta[at["attacker"]] = problem.attacker_position
        if structure.fixed:
            theta[at["controlled"]] = p_d[c].reshape(-1)
            theta[at["held"]] = p_d[~c].reshape(-1)
            theta[at["step_limits"]] = step_limits[c]
        else:  # every defender controlled
            theta[at["controlled"]] = p_d.reshape(-1)
            theta[at["step_limits"]] = step_limits
        theta[at["desired"]] = problem.desired_velocity
        theta[self._scenario_run] = run
        theta[self._scalars] = scalars
        if structure.objective == "enclose":
            e, ref = problem.enclose_weights, problem.enclose_reference
            theta[self._weights] = (0.0, 0.0, e.move, 1.0)
            theta[self._enclose] = (*arena, e.attacker, e.edge, e.edge_margin)
            nc, N = structure.planned, structure.horizon
            steps = theta[at["reference"]].reshape(N, reference_size(nc))
            places = ref.defenders[:, c] if structure.fixed else ref.defenders
            steps[:, : 2 * nc] = places.reshape(N, -1)
            steps[:, 2 * nc : 2 * nc + 2] = ref.attacker
            steps[:, 2 * nc + 2] = ref.slot_weight
        else:
            w = problem.weights
            theta[self._weights] = (w.force, w.ring, w.move, w.equal_distance)


@lru_cache(maxsize=64)
def parameter_writer(structure: Structure) -> ParameterWriter:
    """The :class:`ParameterWriter` of ``structure``, one per process."""
    return ParameterWriter(structure)


def pack(values: dict, structure: Structure) -> np.ndarray:
    """θ from its named parts (:func:`unpack`'s inverse), in the order of :func:`_layout`."""
    return np.concatenate([np.ravel(np.asarray(values[name], dtype=float)) for name, _ in _layout(structure)])


def enclose_residuals(p: dict, attacker, defenders: list, places, attacker_place, weight) -> list:
    """The ``enclose`` objective's residuals at one step (docs/formulations.md).

    Each controlled defender to its place, the attacker to its reference position, and the attacker's
    distance beyond the arena less ``edge_margin`` on each side, all per r̄_d (the mean step, so that a
    step's worth of error costs about one: the QP is then as well scaled as the paper's; a robot planning apart
    reads the team's from θ, so that its objective is the team's with the others held).
    """
    length = p["length"] if "length" in p else ca.sum1(p["step_limits"]) / p["step_limits"].shape[0]
    out = [ca.sqrt(weight) * (d - places[2 * i : 2 * i + 2]) / length for i, d in enumerate(defenders)]
    out.append(ca.sqrt(p["w_attacker"]) * (attacker - attacker_place) / length)
    x_min, y_min, x_max, y_max = (p["arena"][j] for j in range(4))
    margin = p["edge_margin"]
    beyond = ca.vertcat(
        x_min + margin - attacker[0],
        y_min + margin - attacker[1],
        attacker[0] - x_max + margin,
        attacker[1] - y_max + margin,
    )
    out.append(ca.sqrt(p["w_edge"]) * ca.fmax(beyond, 0) / length)
    return out


class CaptureModel:
    """Symbols and expressions of the capture problem for one structure."""

    def __init__(self, structure: Structure):
        self.structure = structure
        self.nc, self.nf, self.m = structure.planned, structure.fixed, structure.obstacles
        self.N, self.objective = structure.horizon, structure.objective
        self.X = ca.SX.sym("X", structure.plan_size)
        self.theta = ca.SX.sym("theta", parameter_size(structure))
        self.p = unpack(self.theta, structure)
        self._build()

    def defender(self, k: int, i: int):
        """p_di at step k+1 (k = 0..N−1) for controlled defender i."""
        start = (k * self.nc + i) * 2
        return self.X[start : start + 2]

    def previous(self, k: int, i: int):
        return self.p["controlled"][2 * i : 2 * i + 2] if k == 0 else self.defender(k - 1, i)

    def held(self, j: int):
        return self.p["held"][2 * j : 2 * j + 2]

    def _resultant(self, p_a, defenders):
        p = self.p
        force = p["nominal"]
        for d in defenders:
            force = force + p["k_d"] * repulsion(p_a - d, p["perception_radius"], p["eta"])
        for o in range(self.m):
            force = force + p["k_o"] * obstacle_repulsion(
                p_a, p["centres"][2 * o : 2 * o + 2], p["radii"][o], p["protective_distance"], p["eta"]
            )
        return force

    def _build(self) -> None:
        p, nc, N = self.p, self.nc, self.N
        held = [self.held(j) for j in range(self.nf)]
        start = [p["controlled"][2 * i : 2 * i + 2] for i in range(nc)] + held
        p_a = p["attacker"] + p["time_step"] * saturate(self._resultant(p["attacker"], start), p["attacker_max_speed"])
        residuals, attacker, sq_dist = [], [], []
        for k in range(N):
            team = [self.defender(k, i) for i in range(nc)] + held
            attacker.append(p_a)
            force = self._resultant(p_a, team)
            if self.objective == "enclose":
                residuals += enclose_residuals(p, p_a, team[:nc], *step_reference(p, k, self.structure))
            else:
                residuals.append(ca.sqrt(p["w_force"]) * (p["desired"] - force) / p["attacker_max_speed"])
            for i in range(nc):
                r = self.defender(k, i) - p_a
                sq_dist.append(ca.dot(r, r) if self.objective == "paper" else ca.SX.zeros(1, 1))  # enclose: no Eq. 14
                if self.objective != "enclose":
                    residuals.append(ca.sqrt(p["w_ring"]) * (norm(r) - p["ring_radius"]) / p["hunt_radius"])
                residuals.append(
                    ca.sqrt(p["w_move"]) * (self.defender(k, i) - self.previous(k, i)) / p["step_limits"][i]
                )
            p_a = p_a + p["time_step"] * saturate(force, p["attacker_max_speed"])
        self.residual = ca.vertcat(*residuals)
        self.attacker = ca.vertcat(*attacker)  # (2N,): attacker at steps 1..N
        self.squared_distance = ca.vertcat(*sq_dist)  # (N·nc,): |r_ai,k|², Eq. 14

    @cached_property
    def squared_distance_function(self) -> ca.Function:
        """(X, θ) ↦ |r_ai,k|² for every step and controlled defender."""
        return ca.Function("squared_distance", [self.X, self.theta], [self.squared_distance])


@lru_cache(maxsize=32)
def capture_model(structure: Structure) -> CaptureModel:
    """The model for one structure, built once per process."""
    return CaptureModel(structure)


def decision_point(problem: CaptureProblem, X: np.ndarray, theta: np.ndarray | None = None) -> np.ndarray:
    """[X, q, s] for positions X: q_k the mean squared distance of step k, s the remaining gaps.

    A point consistent with Eq. 14's elastic form, used as the starting guess.
    """
    model = capture_model(problem.structure)
    theta = parameter_vector(problem) if theta is None else theta
    sq = np.array(model.squared_distance_function(X, theta)).reshape(problem.horizon, -1)
    q = sq.mean(axis=1)
    return np.concatenate([X, q, np.abs(sq - q[:, None]).ravel()])
