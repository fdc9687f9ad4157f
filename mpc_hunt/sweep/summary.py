"""A sweep's summary per strategy, attacker and belief, recomputed from its rows alone (``mpc-hunt sweep-report``).

The success rate counts the hunts that can be captured by definition
(:func:`mpc_hunt.sweep.scenario_row.capturable_by_definition`); the others are
reported apart. Among those, the unreachable ones (no defender can come near
the attacker before it leaves: :mod:`mpc_hunt.sweep.reachability`) are lost by
every controller; ``success_rate_reachable`` leaves them out too.
``success_rate_comfortable`` counts only the comfortable ones (enough
defenders can arrive with time to spare: not a race only a perfect controller
wins). ``success_rate_comfortable_without_edge_race`` leaves out, among those,
the hunts whose attacker could reach some edge of the arena before every
defender (:func:`mpc_hunt.sweep.reachability.edge_race_lost`): lost against an
evader that runs for that edge (a previous version's rows, which lack the
label, count in neither). Each 95 % interval is Wilson's score interval. ``safety_breaches_approach``
and ``_capture`` count the hunts in which a defender came inside an obstacle's
safety distance R_safe in that stage (:func:`mpc_hunt.sweep.outcome.safety_breaches`).
"""

from __future__ import annotations

import math
from collections import Counter

import numpy as np

from mpc_hunt import markdown
from mpc_hunt.sweep.outcome import CAUSES
from mpc_hunt.world.behaviours import DEFAULT_BEHAVIOUR
from mpc_hunt.world.belief import Belief

Z95 = 1.959963984540054


def wilson(successes: int, trials: int, z: float = Z95) -> tuple[float, float]:
    """Wilson's score interval for a binomial proportion; (0, 1) with no trials."""
    if trials == 0:
        return (0.0, 1.0)
    p = successes / trials
    centre = (p + z * z / (2 * trials)) / (1 + z * z / trials)
    half = z * math.sqrt(p * (1 - p) / trials + z * z / (4 * trials * trials)) / (1 + z * z / trials)
    return (max(0.0, centre - half), min(1.0, centre + half))


def _median_iqr(values: list[float]) -> tuple[float | None, float | None]:
    if not values:
        return None, None
    q1, q2, q3 = np.percentile(values, [25, 50, 75])
    return float(q2), float(q3 - q1)


def _least(rows: list[dict], key: str) -> float | None:
    values = [r[key] for r in rows if r.get(key) is not None]
    return min(values) if values else None


def _by_defenders(reachable: list[dict]) -> dict[str, dict]:
    """Success among the reachable hunts, per number of defenders (two need an obstacle as a member)."""
    out = {}
    for n in sorted({r["n_defenders"] for r in reachable}):
        group = [r for r in reachable if r["n_defenders"] == n]
        won = sum(r["outcome"] == "captured" for r in group)
        out[str(n)] = {
            "hunts": len(group),
            "captured": won,
            "success_rate": won / len(group),
            "success_rate_ci95": list(wilson(won, len(group))),
        }
    return out


def combination(row: dict) -> tuple[str, str, str]:
    """A row's (strategy, attacker, belief); a row without the last two ran the paper's attacker, believed
    exactly."""
    return row["strategy"], row.get("attacker", DEFAULT_BEHAVIOUR), row.get("belief", Belief().label())


def best_strategy(summaries: list[dict]) -> str:
    """The strategy with the highest success rate over all its hunts, every attacker and belief pooled (the
    first listed on a tie)."""
    pooled: dict[str, tuple[int, int]] = {}
    for s in summaries:
        won, counted = pooled.get(s["strategy"], (0, 0))
        pooled[s["strategy"]] = (won + s["captured"], counted + s["hunts"] - s["uncapturable_by_definition"])
    return max(pooled, key=lambda k: pooled[k][0] / pooled[k][1] if pooled[k][1] else 0.0)


def summarise(rows: list[dict]) -> list[dict]:
    """One summary per strategy, attacker and belief, in order of first appearance."""
    out = []
    for strategy, attacker, belief in dict.fromkeys(combination(r) for r in rows):
        mine = [r for r in rows if combination(r) == (strategy, attacker, belief)]
        counted = [r for r in mine if r["outcome"] != "uncapturable"]
        won = [r for r in counted if r["outcome"] == "captured"]
        reachable = [r for r in counted if r["reachable"]]
        won_reachable = [r for r in reachable if r["outcome"] == "captured"]
        comfortable = [r for r in counted if r["comfortable"]]
        won_comfortable = [r for r in comfortable if r["outcome"] == "captured"]
        held = [r for r in comfortable if r.get("edge_race_lost") is not None and not r["edge_race_lost"]]
        won_held = [r for r in held if r["outcome"] == "captured"]
        causes = Counter(r["cause"] for r in counted if r["outcome"] == "failed")
        capture_median, capture_iqr = _median_iqr([r["capture_time_s"] for r in won])
        path_median, path_iqr = _median_iqr([r["path_length_m"] for r in won])
        solves = sum(r.get("solves") or 0 for r in mine)
        p50 = [r["solve_time_p50_s"] for r in mine if r.get("solve_time_p50_s") is not None]
        p95 = [r["solve_time_p95_s"] for r in mine if r.get("solve_time_p95_s") is not None]
        out.append(
            {
                "strategy": strategy,
                "attacker": attacker,
                "belief": belief,
                "hunts": len(mine),
                "uncapturable_by_definition": len(mine) - len(counted),
                "captured": len(won),
                "success_rate": len(won) / len(counted) if counted else None,
                "success_rate_ci95": list(wilson(len(won), len(counted))),
                "unreachable": len(counted) - len(reachable),
                "success_rate_reachable": len(won_reachable) / len(reachable) if reachable else None,
                "success_rate_reachable_ci95": list(wilson(len(won_reachable), len(reachable))),
                "reachable_by_defenders": _by_defenders(reachable),
                "comfortable": len(comfortable),
                "success_rate_comfortable": len(won_comfortable) / len(comfortable) if comfortable else None,
                "success_rate_comfortable_ci95": list(wilson(len(won_comfortable), len(comfortable))),
                "comfortable_without_edge_race": len(held),
                "success_rate_comfortable_without_edge_race": len(won_held) / len(held) if held else None,
                "success_rate_comfortable_without_edge_race_ci95": list(wilson(len(won_held), len(held))),
                "failures": {c: causes.get(c, 0) for c in CAUSES},
                "collisions": causes.get("obstacle_collision", 0) + causes.get("defender_contact", 0),
                "capture_time_median_s": capture_median,
                "capture_time_iqr_s": capture_iqr,
                "path_length_median_m": path_median,
                "path_length_iqr_m": path_iqr,
                "min_obstacle_clearance_m": _least(mine, "min_obstacle_clearance_m"),
                "min_defender_separation_m": _least(mine, "min_defender_separation_m"),
                "min_arena_margin_m": _least(mine, "min_arena_margin_m"),
                "safety_breaches_approach": sum(bool(r.get("safety_breach_approach")) for r in mine),
                "safety_breaches_capture": sum(bool(r.get("safety_breach_capture")) for r in mine),
                "solve_time_p50_median_s": float(np.median(p50)) if p50 else None,
                "solve_time_p95_median_s": float(np.median(p95)) if p95 else None,
                "solve_time_max_s": max(
                    (r["solve_time_max_s"] for r in mine if r.get("solve_time_max_s")), default=None
                ),
                "failed_solve_share": (sum(r.get("failed_solves") or 0 for r in mine) / solves) if solves else None,
                "over_time_step_share": (sum(r.get("solves_over_time_step") or 0 for r in mine) / solves)
                if solves
                else None,
            }
        )
    return out


def table(summaries: list[dict]) -> str:
    """The summary as a Markdown table."""

    def pct(x):
        return "–" if x is None else f"{100 * x:.1f} %"

    def num(x, scale=1.0, unit=""):
        return "–" if x is None else f"{x * scale:.3g}{unit}"

    def rate(s, key):
        lo, hi = s[f"{key}_ci95"]
        return f"{pct(s[key])} ({pct(lo)}–{pct(hi)})"

    lines = markdown.table(
        [
            "strategy",
            "attacker",
            "belief",
            "hunts",
            "success (95 % CI)",
            "of reachable hunts",
            "of comfortable hunts",
            "of comfortable hunts without an edge race",
            "failures by cause",
            "capture time median (IQR)",
            "min clearance / separation",
            "inside R_safe approaching / capturing",
            "solve p50 / p95",
            "failed solves",
            "solves over T",
        ],
        "lllrlllllllrlrr",
        (
            [
                s["strategy"],
                s["attacker"],
                s["belief"],
                f"{s['hunts']} ({s['uncapturable_by_definition']} uncapturable, "
                f"{s['unreachable']} unreachable, {s['comfortable']} comfortable)",
                rate(s, "success_rate"),
                rate(s, "success_rate_reachable"),
                rate(s, "success_rate_comfortable"),
                rate(s, "success_rate_comfortable_without_edge_race"),
                ", ".join(f"{k} {v}" for k, v in s["failures"].items() if v) or "none",
                f"{num(s['capture_time_median_s'], unit=' s')} ({num(s['capture_time_iqr_s'], unit=' s')})",
                f"{num(s['min_obstacle_clearance_m'], unit=' m')} / {num(s['min_defender_separation_m'], unit=' m')}",
                f"{s['safety_breaches_approach']} / {s['safety_breaches_capture']} hunts",
                f"{num(s['solve_time_p50_median_s'], 1e3, ' ms')} / {num(s['solve_time_p95_median_s'], 1e3, ' ms')}",
                pct(s["failed_solve_share"]),
                pct(s["over_time_step_share"]),
            ]
            for s in summaries
        ),
    )
    groups = sorted({n for s in summaries for n in s["reachable_by_defenders"]}, key=int)

    def by_defenders(s: dict, n: str) -> str:
        g = s["reachable_by_defenders"].get(n)
        return "–" if g is None else f"{g['captured']} / {g['hunts']}, {rate(g, 'success_rate')}"

    lines += [
        "",
        "Of the reachable hunts, by number of defenders (captured / hunts, success, 95 % CI):",
        "",
        *markdown.table(
            ["strategy", "attacker", "belief", *(f"{n} defenders" for n in groups)],
            "l" * (3 + len(groups)),
            ([s["strategy"], s["attacker"], s["belief"], *(by_defenders(s, n) for n in groups)] for s in summaries),
        ),
    ]
    return "\n".join(lines)
