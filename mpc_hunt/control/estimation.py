"""The attacker's parameters estimated online from its observed track (Eqs. 2 and 9).

The defenders model the attacker as the paper's APF attacker (Eqs. 2 and 9,
:mod:`mpc_hunt.world.attacker`): at step k it moves at

    v_k = sat(u_k, v_a),   u_k = v_nom + g Φ_k(R) + o_k,   Φ_k(R) = Σ_i h(p_a,k − p_di,k; R),

with h(r; R) = (R³/|r|³ − 1) r for |r| < R, else 0 (H of Eq. 2 with η = 1), o_k
the obstacles' known field k_o Σ_o H(r_ao) (Eq. 3), and sat the cap at the top
speed v_a, which the defenders know. The intent v_nom, the gain g = k_d η (k_d
and η are not separately identifiable from the defenders' pushes) and the
perception radius R = R_agg are estimated from the last ``WINDOW`` observed
velocities v_k = (p_a,k+1 − p_a,k)/T (Eq. 7's finite difference), each paired
with the defenders' positions at k.

The fit (docs/estimation.md gives the measurements behind each choice):

* **Objective**: least squares on the track, e_k = T Σ_{j≤k} (sat(u_j) − v_j),
  the model's displacement from the window's first position less the observed
  one: the maximum-likelihood fit for white noise on the observed positions,
  whose differences make the velocities' noise large and correlated.
* **Search**, every ``REFIT`` updates and whenever tracking finds the objective
  ``SURPRISE`` times worse: for a given R the model is linear in θ = (v_nom, g)
  but for the cap. An uncapped sample gives u_k = v_k; a capped one
  (|v_k| = v_a) only u_k = λ_k v_k with λ_k ≥ 1, that is its direction
  (n_k·u_k = 0) and a bound (v̂_k·u_k ≥ |v_k|). That convex problem, exact on
  noise-free data, is solved for ``GRID`` radii at once by an active set on the
  bounds, on ``LEVELS`` nested grids of R (each spanning two steps of the last
  around its best radius). From the best and from the previous estimate,
  Levenberg–Marquardt on (v_nom, log g, log R) minimises the objective.
  Of fits the data cannot tell apart, the search takes the fastest intent: when
  every sample is capped, only the intent's direction and g/|v_nom| are seen,
  and (v_nom, g) is scaled along λ(v_nom, g) up to |v_nom| = v_a (docs/model.md, E6: an
  attacker intends at most v_a) while the fit stays as good.
* **Tracking**, between searches: ``TRACK_STEPS`` Levenberg–Marquardt steps
  from the previous estimate on the shifted window.
* **Identification**: the defenders' field (g and R) counts as seen when it
  explains the track significantly better than the intent alone (an F-ratio
  over ``SIGNIFICANCE``). Otherwise (no defender within any candidate R, too
  few samples) the estimate keeps the prior's g and R, ``identified`` is
  False, and the intent is the fit without pushes. ``speed_identified`` says
  likewise whether scaling (v_nom, g) by ``SCALE_CHANGE`` (10 %) either way
  would worsen the fit significantly (an intent above v_a being excluded).

The prior is the defenders' believed model (:class:`~mpc_hunt.world.belief.AttackerModel`); each update
returns it with the fit put in (k_d = g/η, keeping η). R is searched within
[R₀/RADIUS_SPAN, R₀·RADIUS_SPAN] and g within [g₀/GAIN_SPAN, g₀·GAIN_SPAN].
"""

from __future__ import annotations

import time
from collections import deque
from dataclasses import dataclass

import numpy as np

from mpc_hunt.control.controller import Observation
from mpc_hunt.world.belief import AttackerModel
from mpc_hunt.world.field import FIELD_FLOOR, nominal_intent, obstacle_repulsion
from mpc_hunt.world.geometry import norm
from mpc_hunt.world.scenario import Scenario

WINDOW = 100  # velocity samples kept: 10 s at T = 0.1 s
MIN_SAMPLES = 10  # fewer samples: the prior is kept
REFIT = 10  # updates between two searches (tracking steps in between)
SURPRISE = 10.0  # a tracked objective this many times the last one calls for a search at once
GRID = 9  # perception radii tried per level of the search
RADIUS_SPAN = 3.0  # R within [R₀/3, 3 R₀]
GAIN_SPAN = 1e3  # g within [g₀/10³, 10³ g₀]
LEVELS = 4  # nested grids of the search: the last spaced 0.2 % apart
SEARCH_STEPS = 40  # Levenberg–Marquardt steps after a search, at most (12 left a 2 mm/s intent against g = 1 short)
SETTLED = 1e-9  # they end on a step gaining less than this fraction, or a track error this fraction of v_a T
TRACK_STEPS = 2  # Levenberg–Marquardt steps per update between searches, at most
ACTIVE_SET_STEPS = 6  # active-set iterations of the convex fit
SCALES = 8  # points of the scale search along λ(v_nom, g)
SIGNIFICANCE = 10.0  # F-ratio above which the defenders' field counts as seen
SCALE_CHANGE = 0.1  # the scale of (v_nom, g) counts as seen when changing it this much would be significant
NOISE_FLOOR = 1e-3  # of v_a T: the smallest track error taken as noise
SATURATED = 1.0 - 1e-6  # of v_a: an observed speed at least this counts as capped


@dataclass(frozen=True)
class Estimate:
    """The attacker model fitted to the window, and how far the window supports it (the module's docstring)."""

    model: AttackerModel  # the prior with the fitted v_nom, g = k_d η and R_agg put in (AttackerModel.fitted)
    identified: bool  # the defenders' field was seen: gain and perception_radius were fitted
    speed_identified: bool  # the scale of (v_nom, g) is seen, not only the intent's direction and g/|v_nom|
    # (False too for an intent of zero with no push: it has no scale)
    samples: int  # velocity samples used
    residual: float  # m/s: RMS of the fitted model's velocity error over the samples
    solve_time: float  # s: the cost of this update


def _field(radii: np.ndarray, offsets: np.ndarray, distances: np.ndarray) -> np.ndarray:
    """Φ_k(R) = Σ_i h(p_a − p_di; R) for each radius in ``radii`` (m,): shape (m, K, 2).

    ``offsets`` (K, n, 2) are p_a − p_di, ``distances`` (K, n) their lengths
    (floored as the world's field floors them); R³/d³ − 1 > 0 exactly when d < R.
    """
    return _sum_over_defenders(np.maximum(radii[:, None, None] ** 3 / distances**3 - 1.0, 0.0), offsets)


def _sum_over_defenders(weights: np.ndarray, offsets: np.ndarray) -> np.ndarray:
    """Σ_i weights[m, k, i] offsets[k, i]: shape (m, K, 2)."""
    return np.matmul(weights.transpose(1, 0, 2), offsets).transpose(1, 0, 2)


def _cap(u: np.ndarray, top: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """sat(u) of Eq. 2 along the last axis, with the factor it scaled by and |u|."""
    length = np.sqrt(np.sum(u * u, axis=-1))
    scale = np.minimum(1.0, top / np.maximum(length, 1e-300))
    return u * scale[..., None], scale, length


def _velocities(
    x: np.ndarray, offsets: np.ndarray, distances: np.ndarray, pushes: np.ndarray, top: float, jacobian: bool = True
):
    """The model's velocities sat(u_k) (Eqs. 2 and 9) for parameter rows x = (v_nom, g, R), shape (m, 4), and,
    with ``jacobian``, their derivatives (m, K, 2, 4). ``pushes`` (K, 2) is the obstacles' field o_k."""
    R = x[:, 3]
    phi = _field(R, offsets, distances)
    u = x[:, None, :2] + x[:, 2, None, None] * phi + pushes
    v, scale, length = _cap(u, top)
    if not jacobian:
        return v
    columns = np.zeros(u.shape + (4,))
    columns[..., 0, 0] = columns[..., 1, 1] = 1.0
    columns[..., 2] = phi
    dphi = (distances < R[:, None, None]) * (3 * R[:, None, None] ** 2 / distances**3)
    columns[..., 3] = x[:, 2, None, None] * _sum_over_defenders(dphi, offsets)
    capped = u * ((scale < 1) / np.maximum(length, 1e-300))[..., None]  # û where the cap acts, else 0
    columns -= capped[..., None] * np.sum(capped[..., None] * columns, axis=-2, keepdims=True)
    return v, columns * scale[..., None, None]


class AttackerEstimator:
    """Estimates the attacker's intent, gain and perception radius online (the module's docstring).

    ``prior`` is the defenders' model before any observation (:class:`~mpc_hunt.world.belief.AttackerModel`;
    its top speed and η are taken as known); ``scenario`` gives what else is known: the obstacles, the time step
    and the obstacles' field (Eq. 3, with the model's η). ``update`` once per observation: it returns the
    model updated from the track, which the controller predicts with.
    """

    def __init__(self, scenario: Scenario, prior: AttackerModel):
        self.T, self.top = scenario.hunt.time_step, prior.max_speed
        self.prior_model = prior
        self.prior = np.r_[nominal_intent(np.array(prior.intent), self.top), prior.gain, prior.perception_radius]
        g0, r0 = self.prior[2:]
        self.lower = np.r_[-self.top, -self.top, g0 / GAIN_SPAN, r0 / RADIUS_SPAN]
        self.upper = np.r_[self.top, self.top, g0 * GAIN_SPAN, r0 * RADIUS_SPAN]
        self.scenario = scenario
        self.window: deque = deque(maxlen=WINDOW)
        self.last: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None  # p_a, p_d, o at the last observation
        self.x = self.prior.copy()  # the last fit (v_nom, g, R)
        self.alone = np.r_[self.prior[:2], 0.0, r0]  # the last fit of the intent alone (g = 0: no push)
        self.cost = np.inf  # its objective
        self.updates = 0

    def update(self, obs: Observation) -> Estimate:
        """Add the velocity sample that ``obs`` completes (with the defenders of the previous observation),
        refit, and return the estimate (its model: the prior with the fit put in). Non-finite positions are
        skipped."""
        start = time.perf_counter()
        attacker, defenders = np.asarray(obs.attacker, dtype=float), np.asarray(obs.defenders, dtype=float)
        if self.last is not None and obs.previous_attacker is not None:
            p_a, p_d, push = self.last
            v = (attacker - p_a) / self.T
            if p_d.shape != defenders.shape:  # a different team: the old samples no longer pair up
                self.window.clear()
            elif np.all(np.isfinite(v)) and np.all(np.isfinite(p_d)):
                self.window.append((p_a - p_d, push, v))
        self.last = (attacker, defenders, self._obstacle_push(attacker)) if np.all(np.isfinite(attacker)) else None
        if len(self.window) < MIN_SAMPLES:
            return self._estimate(self.prior, False, False, 0.0, start)
        self._load()
        floor = (NOISE_FLOOR * self.top * self.T) ** 2  # per track coordinate
        # Track the fit and the intent alone; search now and then, or when the tracked fit got much worse.
        self.x, self.alone = self._refine(np.array([self.x, self.alone]), TRACK_STEPS)[0]
        cost, alone_cost = self._cost(np.array([self.x, self.alone]))
        if self.updates % REFIT == 0 or cost > SURPRISE * self.cost + 2 * len(self.window) * floor:
            self.x = self._search()
            cost = self._cost(self.x[None])[0]
        self.updates, self.cost = self.updates + 1, cost
        # Is the field seen (an F-test against the intent alone)? Is the scale: would (v_nom, g) a tenth smaller,
        # or larger (unless that intent exceeds v_a, E6), fit significantly worse?
        noise = max(cost / max(2 * len(self.window) - 4, 1), floor)
        identified = bool(alone_cost - cost > 2 * SIGNIFICANCE * noise)
        fitted = self.x if identified else self.alone
        change = np.array([[1 - SCALE_CHANGE], [1 + SCALE_CHANGE]])  # λ(v_nom, g), λ = 0.9 and 1.1
        worse = self._cost(np.c_[fitted[:3] * change, np.full(2, fitted[3])]) > (
            (cost if identified else alone_cost) + 2 * SIGNIFICANCE * noise
        )
        scaled = bool(worse[0] and (worse[1] or (1 + SCALE_CHANGE) * norm(fitted[:2]) > self.top))
        v = _velocities(fitted[None], self.offsets, self.distances, self.pushes, self.top, jacobian=False)[0]
        residual = float(np.sqrt(np.mean(np.sum((v - self.v) ** 2, axis=-1))))
        return self._estimate(
            fitted if identified else np.r_[self.alone[:2], self.prior[2:]], identified, scaled, residual, start
        )

    def _obstacle_push(self, p_a: np.ndarray) -> np.ndarray:
        """o = k_o Σ_o H(r_ao) (Eqs. 3 and 9), known to the defenders."""
        s, hunt = self.scenario, self.scenario.hunt
        return hunt.k_o * obstacle_repulsion(
            p_a, s.obstacle_centres, s.obstacle_radii, hunt.protective_distance, self.prior_model.eta
        )

    def _estimate(
        self, x: np.ndarray, identified: bool, speed_identified: bool, residual: float, start: float
    ) -> Estimate:
        return Estimate(
            self.prior_model.fitted(x[:2], x[2], x[3]),
            identified,
            speed_identified,
            len(self.window),
            residual,
            time.perf_counter() - start,
        )

    def _load(self) -> None:
        """The window as arrays: offsets floored as the field floors them (FIELD_FLOOR), pushes, velocities."""
        offsets = np.array([s[0] for s in self.window])
        length = norm(offsets)
        self.distances = np.maximum(length, FIELD_FLOOR)
        self.offsets = offsets * (self.distances / np.where(length > 0, length, np.inf))[..., None]
        self.pushes = np.array([s[1] for s in self.window])
        self.v = np.array([s[2] for s in self.window])

    def _track(self, velocities: np.ndarray) -> np.ndarray:
        """The track errors e_k = T Σ_{j≤k} (model − observed), along the samples' axis."""
        return self.T * np.cumsum(velocities - self.v, axis=-2)

    def _cost(self, x: np.ndarray) -> np.ndarray:
        e = self._track(_velocities(x, self.offsets, self.distances, self.pushes, self.top, jacobian=False))
        return np.sum(e**2, axis=(-2, -1))

    def _refine(self, x: np.ndarray, steps: int) -> tuple[np.ndarray, np.ndarray]:
        """Levenberg–Marquardt on the track objective from each row of ``x`` (m, 4), within the bounds.

        It steps in log g and log R: there the valley along which g R³ (a near defender's push) stays put is
        straight, and g = 0 (the intent alone, no push) stays 0. Returns the rows and their objectives.
        """

        def residuals(x):
            v, dv = _velocities(x, self.offsets, self.distances, self.pushes, self.top)
            dv[..., 2:] *= x[:, None, None, 2:]  # d/dlog g, d/dlog R
            return self._track(v).reshape(len(x), -1), self.T * np.cumsum(dv, axis=1).reshape(len(x), -1, 4)

        r, jac = residuals(x)
        cost = np.einsum("mr,mr->m", r, r)
        damping, settled = np.full(len(x), 1e-3), np.zeros(len(x), bool)
        for _ in range(steps):
            hessian = jac.transpose(0, 2, 1) @ jac
            diagonal = np.einsum("mii->mi", hessian)
            shift = damping[:, None] * diagonal + 1e-12 * (diagonal.max(axis=1, keepdims=True) + 1e-300)
            step = np.linalg.solve(hessian + shift[..., None] * np.eye(4), -(jac.transpose(0, 2, 1) @ r[..., None]))
            scaled = np.clip(x[:, 2:] * np.exp(np.clip(step[:, 2:, 0], -9.0, 9.0)), self.lower[2:], self.upper[2:])
            trial = np.c_[_cap(x[:, :2] + step[:, :2, 0], self.top)[0], np.where(x[:, 2:] > 0, scaled, 0.0)]
            r1, jac1 = residuals(trial)
            cost1 = np.einsum("mr,mr->m", r1, r1)
            better = cost1 < cost
            settled |= better & (cost - cost1 <= SETTLED * cost) | (cost <= self._negligible())
            x, r = np.where(better[:, None], trial, x), np.where(better[:, None], r1, r)
            jac, cost = np.where(better[:, None, None], jac1, jac), np.minimum(cost1, cost)
            damping = np.where(better, damping / 3, damping * 4)
            if settled.all():
                break
        return x, cost

    def _search(self) -> np.ndarray:
        """The better of the tracked estimate and the fit from the convex fits over nested grids of radii."""
        centre, span = self.prior[3], RADIUS_SPAN
        for _ in range(LEVELS):
            radii = np.clip(centre * span ** np.linspace(-1.0, 1.0, GRID), self.lower[3], self.upper[3])
            theta, cost = self._convex(radii)
            best = int(np.argmin(cost))
            centre, span = radii[best], span ** (2 / (GRID - 1))
        x, cost = self._refine(np.r_[theta[best], radii[best]][None], SEARCH_STEPS)
        return self._fastest(x[0] if cost[0] < self._cost(self.x[None])[0] else self.x)

    def _convex(self, radii: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """For each radius, θ = (v_nom, g) from the convex fit of the module's docstring, then within the
        bounds; returns θ (m, 3) and the track objective at each."""
        v, K, m = self.v, len(self.v), len(radii)
        speed = norm(v)
        capped = speed >= SATURATED * self.top
        along = v / np.where(speed > 0, speed, 1.0)[:, None]
        across = np.c_[-along[:, 1], along[:, 0]]
        rows = np.where(capped[:, None, None], np.stack([across, along], axis=1), np.eye(2))  # (K, 2, 2)
        bound = np.c_[np.zeros(K, bool), capped].ravel()  # v̂·u ≥ |v| rows
        target = (rows @ (v - self.pushes)[..., None]).ravel()
        phi = _field(radii, self.offsets, self.distances)
        a = np.concatenate([np.broadcast_to(rows, (m, K, 2, 2)), (rows @ phi[..., None])], axis=-1).reshape(m, 2 * K, 3)
        theta = self._bounded(a, np.broadcast_to(target, (m, 2 * K)), bound)
        theta[:, :2] = _cap(theta[:, :2], self.top)[0]
        theta[:, 2] = np.clip(theta[:, 2], self.lower[2], self.upper[2])
        return theta, self._cost(np.c_[theta, radii])

    def _bounded(self, a: np.ndarray, target: np.ndarray, bound: np.ndarray) -> np.ndarray:
        """θ minimising Σ (a_r·θ − target_r)² over the rows r, a row marked ``bound`` counting only while
        a_r·θ < target_r (m problems at once: a is (m, rows, 3)).

        An active set, started from the fit without the bounds. Where those rows leave a direction free (every
        sample capped: the ray λθ), the start is the point on it with the fastest intent, |v_nom| = v_a, on the
        side the bounds point to.
        """
        equal = a * ~bound[:, None]
        values, vectors = np.linalg.eigh(equal.transpose(0, 2, 1) @ a)  # ascending
        kept = values > 1e-10 * values[:, -1:]
        inverse = np.where(kept, 1.0 / np.where(kept, values, 1.0), 0.0)
        theta = np.einsum(
            "mij,mj,mkj,mk->mi", vectors, inverse, vectors, (equal.transpose(0, 2, 1) @ target[..., None])[..., 0]
        )
        free, start = vectors[:, :, 0], theta[:, :2]
        qa, qb = np.sum(free[:, :2] ** 2, axis=1), np.sum(start * free[:, :2], axis=1)
        root = np.sqrt(np.maximum(qb**2 - qa * (np.sum(start**2, axis=1) - self.top**2), 0.0))
        step = (-qb + root) / np.maximum(qa, 1e-300)
        ahead = np.sum((a @ free[..., None])[..., 0] * bound, axis=1) * step >= 0  # the bounds' side
        step = np.where(ahead, step, (-qb - root) / np.maximum(qa, 1e-300))
        theta = np.where(~kept[:, :1] & (qa[:, None] > 1e-12), theta + step[:, None] * free, theta)
        active = np.broadcast_to(~bound, target.shape)
        for _ in range(ACTIVE_SET_STEPS):
            now = ~bound | ((a @ theta[..., None])[..., 0] < target)
            if np.array_equal(now, active):
                break
            active = now
            weighted = a * active[..., None]
            normal = weighted.transpose(0, 2, 1) @ a
            normal += 1e-12 * (np.trace(normal, axis1=1, axis2=2) + 1e-300)[:, None, None] * np.eye(3)
            theta = np.linalg.solve(normal, weighted.transpose(0, 2, 1) @ target[..., None])[..., 0]
        return theta

    def _fastest(self, x: np.ndarray) -> np.ndarray:
        """x = (v_nom, g, R) scaled along λ(v_nom, g) from λ = 1 up to |v_nom| = v_a: the best, and of equals
        the largest (the data fix only g/|v_nom| when every sample is capped). x itself where that would take
        g beyond its bound."""
        reach = self.top / max(float(norm(x[:2])), 1e-300)
        if not 1.0 < reach <= self.upper[2] / x[2]:
            return x
        scaled = np.repeat(x[None], SCALES, axis=0)
        scaled[:, :3] *= np.geomspace(1.0, reach, SCALES)[:, None]
        cost = self._cost(scaled)
        return scaled[np.flatnonzero(cost <= cost.min() * (1 + SETTLED) + self._negligible())[-1]]

    def _negligible(self) -> float:
        """A track objective too small to tell fits apart: an error SETTLED v_a T on every coordinate."""
        return 2 * len(self.v) * (SETTLED * self.top * self.T) ** 2
